#include "shape_separation.h"

#include <algorithm>
#include <cmath>

namespace hfts::robot {
namespace {

constexpr int kBox = 0, kCylinder = 1, kSphere = 2;

/// The segment a direction search starts from: the cylinder's axis, the
/// box's middle segment along its longest edge (spheres are settled before).
void coreSegment(const PlacedShape& s, Eigen::Vector3d& from, Eigen::Vector3d& to) {
  Eigen::Vector3d half = Eigen::Vector3d::Zero();
  if (s.type == kCylinder) {
    half = s.rotation.col(2) * (0.5 * s.size.y());
  } else if (s.type == kBox) {
    Eigen::Index longest = 0;
    s.size.maxCoeff(&longest);
    half = s.rotation.col(longest) * (0.5 * s.size(longest));
  }
  from = s.center - half;
  to = s.center + half;
}

/// The point of the shape nearest to p (p itself when inside).
Eigen::Vector3d closestPoint(const PlacedShape& s, const Eigen::Vector3d& p) {
  Eigen::Vector3d local = s.rotation.transpose() * (p - s.center);
  if (s.type == kBox) {
    local = local.cwiseMax(-0.5 * s.size).cwiseMin(0.5 * s.size);
  } else if (s.type == kCylinder) {
    const double radial = local.head<2>().norm();
    if (radial > s.size.x()) local.head<2>() *= s.size.x() / radial;
    local.z() = std::clamp(local.z(), -0.5 * s.size.y(), 0.5 * s.size.y());
  } else if (local.norm() > s.size.x()) {
    local *= s.size.x() / local.norm();
  }
  return s.center + s.rotation * local;
}

/// True when the shapes' extents along n are more than gap * |n| apart.
bool apartAlong(const PlacedShape& a, const PlacedShape& b, const Eigen::Vector3d& n, double gap) {
  const double norm = n.norm();
  if (!(norm > 1e-12)) return false;
  const double margin = gap * norm;
  return support(a, n) + margin < -support(b, -n) || support(b, n) + margin < -support(a, -n);
}

/// The directions a shape's own geometry suggests: box faces, cylinder axis.
int ownAxes(const PlacedShape& s, Eigen::Vector3d axes[3]) {
  if (s.type == kBox) {
    for (int i = 0; i < 3; ++i) axes[i] = s.rotation.col(i);
    return 3;
  }
  if (s.type == kCylinder) {
    axes[0] = s.rotation.col(2);
    return 1;
  }
  return 0;
}

}  // namespace

double support(const PlacedShape& shape, const Eigen::Vector3d& n) {
  const double atCenter = shape.center.dot(n);
  if (shape.type == kBox) {
    const Eigen::Vector3d local = shape.rotation.transpose() * n;
    return atCenter + 0.5 * shape.size.dot(local.cwiseAbs());
  }
  if (shape.type == kCylinder) {
    const double along = shape.rotation.col(2).dot(n);
    const double across = std::sqrt(std::max(0.0, n.squaredNorm() - along * along));
    return atCenter + 0.5 * shape.size.y() * std::abs(along) + shape.size.x() * across;
  }
  return atCenter + shape.size.x() * n.norm();
}

double closestPointsOfSegments(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                               const Eigen::Vector3d& q0, const Eigen::Vector3d& q1,
                               Eigen::Vector3d& onP, Eigen::Vector3d& onQ) {
  // Minimises |p0 + s d1 - q0 - t d2| over s, t in [0, 1] (Ericson,
  // Real-Time Collision Detection, 5.1.9), degenerate segments included.
  const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  constexpr double kTiny = 1e-18;
  double s = 0.0, t = 0.0;
  if (a <= kTiny && e <= kTiny) {
    // both points
  } else if (a <= kTiny) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= kTiny) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denominator = a * e - b * b;
      s = denominator > kTiny * a * e ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  onP = p0 + s * d1;
  onQ = q0 + t * d2;
  return (onP - onQ).squaredNorm();
}

bool provablyApart(const PlacedShape& a, const PlacedShape& b, double gap) {
  // A sphere against anything: the direction from the other shape's point
  // nearest to its centre separates them whenever they are apart.
  if (a.type == kSphere) return apartAlong(a, b, a.center - closestPoint(b, a.center), gap);
  if (b.type == kSphere) return apartAlong(a, b, b.center - closestPoint(a, b.center), gap);
  Eigen::Vector3d a0, a1, b0, b1, onA, onB;
  coreSegment(a, a0, a1);
  coreSegment(b, b0, b1);
  closestPointsOfSegments(a0, a1, b0, b1, onA, onB);
  if (apartAlong(a, b, onB - onA, gap)) return true;
  if (apartAlong(a, b, b.center - a.center, gap)) return true;
  Eigen::Vector3d axesA[3], axesB[3];
  const int countA = ownAxes(a, axesA), countB = ownAxes(b, axesB);
  for (int i = 0; i < countA; ++i)
    if (apartAlong(a, b, axesA[i], gap)) return true;
  for (int j = 0; j < countB; ++j)
    if (apartAlong(a, b, axesB[j], gap)) return true;
  if (a.type != kBox || b.type != kBox) return false;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (apartAlong(a, b, axesA[i].cross(axesB[j]), gap)) return true;
  return false;
}

}  // namespace hfts::robot
