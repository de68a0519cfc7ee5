// The load capacity of a grasp (load_capacity.h): one linear program per
// load case, solved exactly by CGAL's LP solver. CGAL's headers stay here.
#include "grasp/load_capacity.h"

#include <CGAL/Gmpzf.h>
#include <CGAL/QP_functions.h>
#include <CGAL/QP_models.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/invalid_argument.h"
#include "grasp/grasp_quality.h"
#include "robot/fingertip_geometry.h"
#include "robot/kinematics.h"
#include "robot/link_spheres.h"
#include "robot/object_surface.h"

namespace hfts::grasp {
namespace {

using Program = CGAL::Quadratic_program<double>;
using Solution = CGAL::Quadratic_program_solution<CGAL::Gmpzf>;

void check(bool ok, const std::string& field, const std::string& problem) {
  if (!ok) throw InvalidArgument(field, problem);
}

void validate(const LoadCapacityRequest& r) {
  const Eigen::Index n = r.positions.cols();
  check(n > 0, "positions", "no contacts");
  check(r.normals.cols() == n, "normals", "one per contact position expected");
  check(static_cast<Eigen::Index>(r.jacobians.size()) == n, "jacobians",
        "one per contact position expected");
  check(r.positions.allFinite() && r.normals.allFinite(), "positions", "must be finite");
  check(r.efforts.size() > 0 && r.efforts.allFinite() && (r.efforts.array() > 0.0).all(), "efforts",
        "must be finite numbers > 0");
  for (std::size_t i = 0; i < r.jacobians.size(); ++i)
    check(r.jacobians[i].rows() == 6 && r.jacobians[i].cols() == r.efforts.size() &&
              r.jacobians[i].allFinite(),
          "jacobians[" + std::to_string(i) + "]", "must be finite, 6 x the hand's DoF");
  check(std::isfinite(r.weight) && r.weight > 0.0, "weight", "must be a finite number > 0");
  check(r.center.allFinite(), "center", "must be finite");
  check(r.down.allFinite() && std::abs(r.down.norm() - 1.0) < 1e-6, "down",
        "must be a unit vector");
  // The cone and the torsion: as for epsilon.
  check(std::isfinite(r.friction) && r.friction > 0, "friction", "must be > 0");
  check(r.cone_edges >= 3 && r.cone_edges <= 64, "cone_edges", "must be in 3..64");
  check(std::isfinite(r.torsional_friction) && r.torsional_friction >= 0, "torsional_friction",
        "must be >= 0");
}

/// The DoF forces each primitive wrench (a column of contactWrenches about
/// the centre, unscaled) needs of the hand: J^T [f; m], with m the moment
/// about the contact's normal that the column adds to (p - c) x f.
Eigen::MatrixXd dofForces(const LoadCapacityRequest& r,
                          const Eigen::Matrix<double, 6, Eigen::Dynamic>& wrenches) {
  const Eigen::Index perContact = wrenches.cols() / r.positions.cols();
  Eigen::MatrixXd out(r.efforts.size(), wrenches.cols());
  for (Eigen::Index e = 0; e < wrenches.cols(); ++e) {
    const Eigen::Index i = e / perContact;
    const Eigen::Vector3d f = wrenches.col(e).head<3>();
    Eigen::Matrix<double, 6, 1> load;
    load << f, wrenches.col(e).tail<3>() - (r.positions.col(i) - r.center).cross(f);
    out.col(e) = r.jacobians[static_cast<std::size_t>(i)].transpose() * load;
  }
  return out;
}

/// The largest s in [0, kUnboundedLoad] for which contact forces hold the
/// external force s * load (at the centre of mass) within the efforts.
double largestScale(const Eigen::Matrix<double, 6, Eigen::Dynamic>& wrenches,
                    const Eigen::MatrixXd& dof, const Eigen::VectorXd& efforts,
                    const Eigen::Vector3d& load) {
  if (load.norm() < 1e-12) return kUnboundedLoad;
  const int n = static_cast<int>(wrenches.cols());
  const int scale = n;  // the last variable
  // Rows 0-5: sum of a_e w_e + s [load; 0] = 0. Then |sum of a_e dof_e| <= effort.
  Program lp(CGAL::EQUAL, true, 0.0, false, 0.0);
  for (int e = 0; e < n; ++e)
    for (int row = 0; row < 6; ++row)
      if (wrenches(row, e) != 0.0) lp.set_a(e, row, wrenches(row, e));
  for (int row = 0; row < 3; ++row) lp.set_a(scale, row, load(row));
  for (int row = 0; row < 6; ++row) lp.set_b(row, 0.0);
  for (Eigen::Index d = 0; d < dof.rows(); ++d) {
    const int up = 6 + 2 * static_cast<int>(d), down = up + 1;
    for (int e = 0; e < n; ++e) {
      if (dof(d, e) == 0.0) continue;
      lp.set_a(e, up, dof(d, e));
      lp.set_a(e, down, -dof(d, e));
    }
    lp.set_r(up, CGAL::SMALLER);
    lp.set_r(down, CGAL::SMALLER);
    lp.set_b(up, efforts(d));
    lp.set_b(down, efforts(d));
  }
  lp.set_u(scale, true, kUnboundedLoad);
  lp.set_c(scale, -1.0);
  const Solution solution = CGAL::solve_linear_program(lp, CGAL::Gmpzf());
  if (!solution.is_optimal()) return 0.0;  // s = 0 is always feasible: not reached
  return std::clamp(-CGAL::to_double(solution.objective_value()), 0.0, kUnboundedLoad);
}

/// A contact point of a fingertip with the mesh's outward normal there
/// (object frame).
struct PatchPoint {
  Eigen::Vector3d point;
  Eigen::Vector3d outward;
};

/// Cross product of (b - a) and (c - a) in the plane.
double turn(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const Eigen::Vector2d u = b - a, v = c - a;
  return u.x() * v.y() - u.y() * v.x();
}

/// The corners of the convex hull of `points` (monotone chain) as indices.
std::vector<std::size_t> hullCorners(const std::vector<Eigen::Vector2d>& points) {
  std::vector<std::size_t> order(points.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return points[a].x() < points[b].x() ||
           (points[a].x() == points[b].x() && points[a].y() < points[b].y());
  });
  if (order.size() < 3) return order;
  std::vector<std::size_t> hull(2 * order.size());
  std::size_t k = 0;
  for (int pass = 0; pass < 2; ++pass) {
    const std::size_t start = k;
    for (std::size_t n = 0; n < order.size(); ++n) {
      const std::size_t i = pass == 0 ? order[n] : order[order.size() - 1 - n];
      while (k >= start + 2 && turn(points[hull[k - 2]], points[hull[k - 1]], points[i]) <= 0.0)
        --k;
      hull[k++] = i;
    }
    --k;  // the last point of a pass starts the next
  }
  hull.resize(k);
  return hull;
}

/// Where a fingertip pad lying on the surface touches it: the corners of
/// the patch of surface points within kPatchDepth of the fingertip link,
/// from a grid over a disc of 1.5 pad radii around the contact; the
/// contact alone when that patch is a point.
std::vector<PatchPoint> contactPatch(const robot::ObjectSurface& surface, const robot::Link& link,
                                     const Eigen::Isometry3d& linkInObject,
                                     const FingerClosure& finger, double padRadius) {
  constexpr double kPatchDepth = 5e-4;  // m: about how far servo-pressed pads sink in physics
  constexpr int kHalf = 4;              // a 9 x 9 grid
  std::vector<PatchPoint> touching;
  const Eigen::Vector3d n = finger.outward_normal.normalized();
  const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
  const double step = 1.5 * padRadius / kHalf;
  std::vector<Eigen::Vector2d> plane;
  for (int i = -kHalf; i <= kHalf && step > 0.0; ++i)
    for (int j = -kHalf; j <= kHalf; ++j) {
      if (i * i + j * j > kHalf * kHalf) continue;
      const Eigen::Vector3d g = finger.contact + step * (i * u + j * v);
      const robot::SurfacePoint s = surface.nearest(g);
      const Eigen::Vector3d off = s.point - g;
      if ((off - off.dot(n) * n).norm() > step / 2 || s.normal.dot(n) < 0.5) continue;
      if (robot::signedDistance(link, linkInObject.inverse() * s.point) > kPatchDepth) continue;
      touching.push_back({s.point, s.normal});
      const Eigen::Vector3d d = s.point - finger.contact;
      plane.emplace_back(d.dot(u), d.dot(v));
    }
  if (touching.size() < 2) return {{finger.contact, finger.outward_normal}};
  std::vector<PatchPoint> corners;
  for (const std::size_t i : hullCorners(plane)) corners.push_back(touching[i]);
  return corners;
}

}  // namespace

LoadCapacity loadCapacity(const LoadCapacityRequest& request) {
  validate(request);
  GraspQualityRequest cone;
  cone.positions = request.positions;
  cone.normals = request.normals;
  cone.center = request.center;
  // The pyramid around the friction cone, not inside it: the capacity is
  // then an upper bound, and below 1 the grasp cannot hold.
  cone.friction = request.friction / std::cos(M_PI / request.cone_edges);
  cone.cone_edges = request.cone_edges;
  cone.torsional_friction = request.torsional_friction;
  const Eigen::Matrix<double, 6, Eigen::Dynamic> wrenches = contactWrenches(cone);
  const Eigen::MatrixXd dof = dofForces(request, wrenches);
  const Eigen::Vector3d weight = request.weight * request.down;
  LoadCapacity out;
  for (int c = 0; c < kLoadCases; ++c) {
    Eigen::Vector3d load = weight;
    if (c > 0) load((c - 1) / 2) += (c % 2 == 1 ? 1.0 : -1.0) * request.weight;
    out.per_case[static_cast<std::size_t>(c)] = largestScale(wrenches, dof, request.efforts, load);
  }
  out.factor = *std::min_element(out.per_case.begin(), out.per_case.end());
  return out;
}

LoadCapacityRequest loadRequest(const robot::RobotModel& robot, const Eigen::VectorXd& q,
                                const Eigen::Isometry3d& base, const HandClosure& closure,
                                const Eigen::Isometry3d& object_pose,
                                const Eigen::Vector3d& center_of_mass, double mass,
                                const robot::ObjectSurface* surface) {
  if (!robot.handActuation())
    throw InvalidArgument("robot.hand_actuation",
                          "robot '" + robot.name() + "' has no hand_actuation in its config");
  if (!closure.touches())
    throw InvalidArgument("closure", "not every pad touches: " + closure.failure(robot));
  constexpr double kGravity = 9.81;
  const robot::LinkPoses poses = robot::forwardKinematics(robot, q);
  const int arm = robot.numArmDofs(), hand = robot.numHandDofs();
  const Eigen::Isometry3d baseInObject = object_pose.inverse() * base;
  std::vector<PatchPoint> points;
  std::vector<int> links;  // the fingertip link of each point
  for (std::size_t i = 0; i < robot.fingertips().size(); ++i) {
    const robot::Fingertip& tip = robot.fingertips()[i];
    const FingerClosure& finger = closure.fingers[i];
    const std::vector<PatchPoint> patch =
        surface == nullptr
            ? std::vector<PatchPoint>{{finger.contact, finger.outward_normal}}
            : contactPatch(*surface, robot.links()[static_cast<std::size_t>(tip.link)],
                           baseInObject * poses[static_cast<std::size_t>(tip.link)], finger,
                           robot::padRadius(robot, tip));
    points.insert(points.end(), patch.begin(), patch.end());
    links.insert(links.end(), patch.size(), tip.link);
  }
  LoadCapacityRequest r;
  r.positions.resize(3, static_cast<Eigen::Index>(points.size()));
  r.normals.resize(3, static_cast<Eigen::Index>(points.size()));
  const Eigen::Isometry3d baseInverse = base.inverse();
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Eigen::Vector3d contact = object_pose * points[k].point;
    const auto col = static_cast<Eigen::Index>(k);
    r.positions.col(col) = contact;
    r.normals.col(col) = -(object_pose.linear() * points[k].outward).normalized();
    const auto link = static_cast<std::size_t>(links[k]);
    const Eigen::Vector3d onLink = poses[link].inverse() * (baseInverse * contact);
    const Eigen::Matrix<double, 6, Eigen::Dynamic> j =
        robot::jacobian(robot, poses, links[k], onLink);
    Eigen::MatrixXd world(6, hand);
    world.topRows<3>() = base.linear() * j.block(0, arm, 3, hand);
    world.bottomRows<3>() = base.linear() * j.block(3, arm, 3, hand);
    r.jacobians.push_back(std::move(world));
  }
  r.efforts = robot.handActuation()->efforts;
  r.center = object_pose * center_of_mass;
  r.weight = mass * kGravity;
  r.torsional_friction = robot.torsionalFriction();
  return r;
}

}  // namespace hfts::grasp
