#pragma once
// The trajectory of a planned grasp (docs/trajectories.md): the approach
// (start -> pre-grasp) as a time-optimal trajectory with blended corners,
// then the hand closing from the pre-grasp opening onto the contacts, both
// at rest at their ends, every sample checked by the exact collision
// checker.

#include <Eigen/Core>

#include <string>
#include <vector>

#include "planner/time_parameterization.h"
#include "robot/collision_checker.h"

namespace hfts::planner {

/// A planned grasp's trajectory, sampled at a fixed rate.
struct GraspTrajectory {
  std::vector<TrajectoryPoint> points;  ///< from 0 to duration, the last at duration
  double duration = 0.0;                ///< s
  double closing_start = 0.0;           ///< s: the arm is at the pre-grasp, the hand closes
  /// Largest distance of the approach from the planned path (rad); smaller
  /// than asked when a blend had to be tightened to stay collision-free.
  double deviation = 0.0;
};

/// The trajectory of `path` (start, ..., pre-grasp, grasp: PlanResult::path)
/// under the robot's velocity limits (URDF) and acceleration limits
/// (config `max_accelerations`), sampled every 1 / rate s. The approach's
/// blends may leave the path by at most `maxDeviation` (rad); if a sample
/// or the chord between two samples collides (full rule; the closing:
/// fingertips may touch the target) at `resolution` (Eq. (3) metric), the
/// blends are tightened (deviation / 4, ..., then none: the planned path
/// exactly). Throws InvalidArgument ("trajectory_rate") for a rate that is
/// not positive, ("path") for fewer than two configurations, and
/// robot::ModelError when the robot has no acceleration limits; returns
/// nothing (empty points) when even the exact path's samples collide, or
/// when the trajectory would hold more than kMaxTrajectorySamples states.
GraspTrajectory graspTrajectory(const std::vector<Eigen::VectorXd>& path,
                                robot::CollisionChecker& checker, double resolution, double rate,
                                double maxDeviation = TrajectoryOptions{}.max_deviation);

}  // namespace hfts::planner
