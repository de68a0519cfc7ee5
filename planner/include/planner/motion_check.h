#pragma once
// How the motions a plan returns are checked at the end (docs/planning.md
// "Certified paths"): every segment proven free with a clearance
// (robot::certifyPath, conservative advancement), or, with certification
// off, sampled at a resolution as before issue 45.

#include <Eigen/Core>

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "robot/collision_checker.h"
#include "robot/motion_bound.h"
#include "robot/segment_certificate.h"

namespace hfts::planner {

struct MotionCheck {
  /// Eq. (3) metric: the sampled check's resolution, and the closing
  /// motion's (whose fingertip depth in the target is sampled either way).
  double resolution = 0.0025;
  /// The robot's bound (PlanningWorld::motionBound): motions are proven
  /// free; null: sampled at `resolution`.
  const robot::MotionBound* bound = nullptr;
  /// m: what the proof keeps (robot::CertifyOptions::clearance).
  double clearance = 0.0;

  bool certifies() const { return bound != nullptr; }
};

/// What checking one motion found.
struct MotionVerdict {
  bool free = false;
  /// Proven: the smallest distance the proof measured (m); sampled: none.
  std::optional<double> clearance;
  std::size_t queries = 0;  ///< distance queries of the proof
};

/// Checks the polyline `waypoints` as `check` says, under `rule`: proven
/// (robot::certifyPath, given up when `stop` returns true), or sampled
/// (the first waypoint and every segment at check.resolution; the full rule,
/// or for robot::CertifyRule::kClosing the grasp rule).
MotionVerdict checkMotion(robot::CollisionChecker& checker, const MotionCheck& check,
                          const std::vector<Eigen::VectorXd>& waypoints, robot::CertifyRule rule,
                          const std::function<bool()>& stop = {});

}  // namespace hfts::planner
