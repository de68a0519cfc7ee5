// Ferrari-Canny epsilon through Qhull's 6-D convex hull. Qhull's C headers
// stay in this file.
#include "grasp/grasp_quality.h"

#include "wrench_hull.h"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <string>

#include "core/invalid_argument.h"

namespace hfts::grasp {
namespace {

constexpr double kUnitTolerance = 1e-6;

void check(bool ok, const std::string& field, const std::string& problem) {
  if (!ok) throw InvalidArgument(field, problem);
}

void validate(const GraspQualityRequest& r) {
  check(r.positions.cols() > 0, "positions", "no contacts");
  check(r.positions.cols() == r.normals.cols(), "normals", "one per contact position expected");
  check(r.positions.allFinite(), "positions", "must be finite");
  check(r.normals.allFinite(), "normals", "must be finite");
  for (Eigen::Index i = 0; i < r.normals.cols(); ++i)
    check(std::abs(r.normals.col(i).norm() - 1.0) <= kUnitTolerance,
          "normals[" + std::to_string(i) + "]", "must be a unit vector");
  check(r.center.allFinite(), "center", "must be finite");
  check(std::isfinite(r.torque_scale) && r.torque_scale > 0, "torque_scale", "must be > 0");
  check(std::isfinite(r.friction) && r.friction > 0, "friction", "must be > 0");
  check(r.cone_edges >= 3 && r.cone_edges <= 64, "cone_edges", "must be in 3..64");
  check(std::isfinite(r.torsional_friction) && r.torsional_friction >= 0, "torsional_friction",
        "must be >= 0");
}

/// Qhull's error messages go to a FILE; ours are exceptions or a 0 result.
FILE* nullStream() {
  static FILE* stream = std::fopen("/dev/null", "w");
  return stream;
}

/// Smallest distance from the origin to a facet of the hull of the points
/// (columns), or 0 if the origin is not strictly inside.
double originDepth(Eigen::Matrix<double, 6, Eigen::Dynamic> points) {
  qhT context;
  qhT* qh = &context;
  qh_zero(qh, nullStream());
  char options[] = "qhull Qt";
  const int status = qh_new_qhull(qh, 6, static_cast<int>(points.cols()), points.data(), False,
                                  options, nullptr, nullStream());
  double depth = 0.0;
  if (status == 0) {
    depth = std::numeric_limits<double>::infinity();
    facetT* facet;
    FORALLfacets {
      // Facet hyperplane: normal . x + offset = 0, inside where it is < 0.
      depth = std::min(depth, -facet->offset);
    }
    // The same tolerance as the incremental hull: an origin within
    // rounding of a facet is on the boundary, not strictly inside.
    if (!(depth > 1e-11 * points.cwiseAbs().maxCoeff())) depth = 0.0;
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  return depth;
}

/// The contacts' centroid and the normal of their best-fit plane.
struct ContactPlane {
  Eigen::Vector3d mean;
  Eigen::Vector3d normal;
};

ContactPlane contactPlane(const Eigen::Matrix3Xd& positions) {
  const Eigen::Vector3d mean = positions.rowwise().mean();
  const Eigen::Matrix3Xd centered = positions.colwise() - mean;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> pca(centered * centered.transpose());
  return {mean, pca.eigenvectors().col(0)};
}

/// Where the first cone edge of each contact points: the tangent part of a
/// direction defined by the grasp itself (normal of the contacts' best-fit
/// plane, then towards their centroid, then towards the centre), so that
/// epsilon does not change when the grasp and its centre move rigidly or
/// the contacts are reordered. World axes are the last resort.
Eigen::Vector3d firstTangent(const GraspQualityRequest& r, const ContactPlane& plane,
                             Eigen::Index i, const Eigen::Vector3d& normal) {
  const Eigen::Vector3d candidates[] = {plane.normal, plane.mean - r.positions.col(i),
                                        r.center - r.positions.col(i), Eigen::Vector3d::UnitX(),
                                        Eigen::Vector3d::UnitY()};
  for (const Eigen::Vector3d& e : candidates) {
    const Eigen::Vector3d tangent = e - normal * normal.dot(e);
    if (tangent.norm() > 1e-6 * std::max(1.0, e.norm())) return tangent.normalized();
  }
  return normal.unitOrthogonal();
}

}  // namespace

Eigen::Matrix<double, 6, Eigen::Dynamic> contactWrenches(const GraspQualityRequest& r) {
  validate(r);
  const Eigen::Index n = r.positions.cols();
  const int k = r.cone_edges;
  const bool soft = r.torsional_friction > 0.0;
  const int perContact = soft ? k + 2 : k;
  const double sign = r.direction == NormalDirection::kInward ? 1.0 : -1.0;
  Eigen::Matrix<double, 6, Eigen::Dynamic> w(6, n * perContact);
  const ContactPlane plane = contactPlane(r.positions);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d normal = sign * r.normals.col(i).normalized();
    const Eigen::Vector3d t1 = firstTangent(r, plane, i, normal);
    const Eigen::Vector3d t2 = normal.cross(t1);
    const Eigen::Vector3d arm = (r.positions.col(i) - r.center) / r.torque_scale;
    for (int e = 0; e < k; ++e) {
      const double angle = 2.0 * M_PI * e / k;
      const Eigen::Vector3d f = normal + r.friction * (std::cos(angle) * t1 + std::sin(angle) * t2);
      w.col(i * perContact + e) << f, arm.cross(f);
    }
    if (soft) {
      const Eigen::Vector3d twist = (r.torsional_friction / r.torque_scale) * normal;
      w.col(i * perContact + k) << normal, arm.cross(normal) + twist;
      w.col(i * perContact + k + 1) << normal, arm.cross(normal) - twist;
    }
  }
  return w;
}

GraspQualityResult graspQuality(const GraspQualityRequest& request) {
  const Eigen::Matrix<double, 6, Eigen::Dynamic> w = contactWrenches(request);
  GraspQualityResult result;
  // The origin can only be strictly inside a full-dimensional hull.
  if (w.cols() < 7) return result;
  // The specialised hull is exact and fast; Qhull is the fallback for
  // the rare sets where rounding makes its bookkeeping inconsistent.
  const std::optional<double> fast = request.use_qhull ? std::nullopt : originDepthIncremental(w);
  result.epsilon = fast ? *fast : originDepth(w);
  return result;
}

}  // namespace hfts::grasp
