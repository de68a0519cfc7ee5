#include "grasp/stable_placements.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/convex_hull_2.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numeric>
#include <set>
#include <string>

#include "core/invalid_argument.h"

namespace hfts::grasp {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point2 = Kernel::Point_2;

/// Two faces whose normals are nearer than this (rad, 2 degrees) are one
/// way of resting: a scan's flat bottom is many hull triangles.
constexpr double kSameFaceAngle = 0.035;

/// Signed distance (m) from p to the convex polygon `corners` (counter-
/// clockwise): positive inside (to the nearest edge), negative outside.
double signedDepth(const std::vector<Point2>& corners, const Eigen::Vector2d& p) {
  if (corners.empty()) return -std::numeric_limits<double>::infinity();
  double inside = std::numeric_limits<double>::infinity();
  double outside = std::numeric_limits<double>::infinity();
  bool in = corners.size() >= 3;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const Point2& a = corners[i];
    const Point2& b = corners[(i + 1) % corners.size()];
    const Eigen::Vector2d ea(a.x(), a.y()), eb(b.x(), b.y());
    const Eigen::Vector2d edge = eb - ea;
    const double length = edge.norm();
    if (length > 0.0) {
      // Left of every counter-clockwise edge: inside.
      const double left = (edge.x() * (p - ea).y() - edge.y() * (p - ea).x()) / length;
      if (left < 0.0) in = false;
      inside = std::min(inside, left);
    }
    const double t =
        length > 0.0 ? std::clamp((p - ea).dot(edge) / (length * length), 0.0, 1.0) : 0.0;
    outside = std::min(outside, (ea + t * edge - p).norm());
  }
  return in ? inside : -outside;
}

double polygonArea(const std::vector<Point2>& corners) {
  double twice = 0.0;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const Point2& a = corners[i];
    const Point2& b = corners[(i + 1) % corners.size()];
    twice += a.x() * b.y() - b.x() * a.y();
  }
  return std::abs(twice) / 2;
}

void checkOptions(const PlacementOptions& options) {
  if (!std::isfinite(options.contact_tolerance) || options.contact_tolerance < 0.0)
    throw InvalidArgument(
        "options.contact_tolerance",
        "must be a finite distance >= 0 (m), not " + std::to_string(options.contact_tolerance));
  if (!std::isfinite(options.min_margin) || options.min_margin < 0.0)
    throw InvalidArgument("options.min_margin", "must be a finite distance >= 0 (m), not " +
                                                    std::to_string(options.min_margin));
  if (!(options.min_tipping_angle >= 0.0 && options.min_tipping_angle < M_PI / 2))
    throw InvalidArgument(
        "options.min_tipping_angle",
        "must be an angle in [0, pi/2) (rad), not " + std::to_string(options.min_tipping_angle));
}

}  // namespace

std::vector<RestingFace> stablePlacements(const db::ObjectGeometry& object,
                                          const PlacementOptions& options) {
  checkOptions(options);
  const db::Points3& vertices = object.hull_vertices;
  const db::Faces3& faces = object.hull_faces;
  const Eigen::Vector3d& com = object.center_of_mass;
  // The hull's triangles, largest first: a face's normal is its largest
  // triangle's.
  std::vector<Eigen::Vector3d> normals;
  std::vector<double> areas;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3d a = vertices.row(faces(f, 0)).transpose();
    const Eigen::Vector3d b = vertices.row(faces(f, 1)).transpose();
    const Eigen::Vector3d c = vertices.row(faces(f, 2)).transpose();
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    if (cross.norm() <= 0.0) continue;
    normals.push_back(cross.normalized());
    areas.push_back(cross.norm() / 2);
  }
  std::vector<std::size_t> order(normals.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return areas[a] > areas[b]; });

  std::vector<RestingFace> kept;
  std::set<std::vector<Eigen::Index>> seen;  // contact vertex sets already rated
  for (const std::size_t t : order) {
    const Eigen::Vector3d& n = normals[t];
    const bool near = std::any_of(kept.begin(), kept.end(), [&](const RestingFace& face) {
      return std::acos(std::clamp(face.normal.dot(n), -1.0, 1.0)) < kSameFaceAngle;
    });
    if (near) continue;
    const double offset = (vertices * n).maxCoeff();
    std::vector<Eigen::Index> touching;
    for (Eigen::Index v = 0; v < vertices.rows(); ++v)
      if (vertices.row(v).dot(n) >= offset - options.contact_tolerance) touching.push_back(v);
    if (!seen.insert(touching).second) continue;
    // The contact polygon in the plane's coordinates (u, w).
    const Eigen::Vector3d u = n.unitOrthogonal(), w = n.cross(u);
    std::vector<Point2> points;
    for (const Eigen::Index v : touching) {
      const Eigen::Vector3d p = vertices.row(v).transpose();
      points.emplace_back(p.dot(u), p.dot(w));
    }
    std::vector<Point2> corners;
    CGAL::convex_hull_2(points.begin(), points.end(), std::back_inserter(corners));
    const double margin = signedDepth(corners, Eigen::Vector2d(com.dot(u), com.dot(w)));
    if (margin < options.min_margin) continue;
    RestingFace face;
    face.normal = n;
    face.offset = offset;
    face.polygon.resize(3, static_cast<Eigen::Index>(corners.size()));
    for (std::size_t i = 0; i < corners.size(); ++i)
      face.polygon.col(static_cast<Eigen::Index>(i)) =
          offset * n + corners[i].x() * u + corners[i].y() * w;
    face.area = polygonArea(corners);
    face.margin = margin;
    face.height = offset - com.dot(n);
    face.tipping_angle = std::atan2(margin, face.height);
    if (face.tipping_angle < options.min_tipping_angle) continue;
    face.rotation =
        Eigen::Quaterniond::FromTwoVectors(n, -Eigen::Vector3d::UnitZ()).toRotationMatrix();
    kept.push_back(std::move(face));
  }
  std::stable_sort(kept.begin(), kept.end(), [](const RestingFace& a, const RestingFace& b) {
    return a.tipping_angle > b.tipping_angle;
  });
  return kept;
}

Eigen::Isometry3d restingPose(const RestingFace& face, const Eigen::Vector3d& centerOfMass,
                              const Eigen::Vector2d& xy, double yaw, double top) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() =
      Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * face.rotation;
  // The face's plane (normal . v = offset) goes to height `top`: a point
  // v of it lands at z = t_z + (R v)_z = t_z - offset.
  const Eigen::Vector3d com = pose.linear() * centerOfMass;
  pose.translation() = Eigen::Vector3d(xy.x() - com.x(), xy.y() - com.y(), top + face.offset);
  return pose;
}

}  // namespace hfts::grasp
