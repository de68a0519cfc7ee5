#pragma once
// The trajectory of a planned grasp (docs/trajectories.md): the approach
// (start -> pre-grasp) as a time-optimal trajectory with blended corners,
// then the hand closing from the pre-grasp opening onto the contacts, both
// at rest at their ends, the chords between the samples proven free (or
// sampled) as the plan's path was (motion_check.h).

#include <Eigen/Core>

#include <string>
#include <vector>

#include "planner/motion_check.h"
#include "planner/time_parameterization.h"
#include "robot/collision_checker.h"

namespace hfts::planner {

/// A planned grasp's trajectory, sampled at a fixed rate.
struct GraspTrajectory {
  std::vector<TrajectoryPoint> points;  ///< from 0 to duration, the last at duration
  double duration = 0.0;                ///< s
  /// s: the arm is at the pre-grasp, the hand closes (a motion plan's:
  /// the duration).
  double closing_start = 0.0;
  /// s: the hand is closed, the palm lifts the object (PlanResult::lift;
  /// without one: the duration).
  double lift_start = 0.0;
  /// s, with PlanResult::place (else the duration): the carry has brought
  /// the object above its place and the palm descends (place_start); the
  /// object rests there and the hand opens (release_start); the open hand
  /// retreats (retreat_start). The carry runs from the lift's end to
  /// place_start.
  double carry_start = 0.0;
  double place_start = 0.0;
  double release_start = 0.0;
  double retreat_start = 0.0;
  /// Largest distance of the approach from the planned path (rad); smaller
  /// than asked when a blend had to be tightened to stay collision-free.
  double deviation = 0.0;
};

/// The trajectory of `path` (start, ..., pre-grasp, grasp: PlanResult::path)
/// under the robot's velocity limits (URDF) and acceleration limits
/// (config `max_accelerations`), sampled every 1 / rate s. The approach's
/// blends may leave the path by at most `maxDeviation` (rad); if the
/// polyline through its samples fails `check` (the approach rule; the
/// closing's samples the closing rule), the blends are tightened
/// (deviation / 4, ..., then none: the planned path exactly). `queries`,
/// when given, gets the proofs' distance queries. Throws InvalidArgument
/// ("trajectory_rate") for a rate that is not positive, ("path") for fewer
/// than two configurations, and robot::ModelError when the robot has no
/// acceleration limits; returns nothing (empty points) when even the exact
/// path's samples fail, or when the trajectory would hold more than
/// kMaxTrajectorySamples states.
GraspTrajectory graspTrajectory(const std::vector<Eigen::VectorXd>& path,
                                robot::CollisionChecker& checker, const MotionCheck& check,
                                double rate, std::size_t* queries = nullptr,
                                double maxDeviation = TrajectoryOptions{}.max_deviation);

/// The trajectory of a motion plan's path (start, ..., goal: motion_goal.h)
/// as graspTrajectory's approach, without a closing (closing_start =
/// duration); its samples' polyline checked as transit. `speed` (in (0,
/// 1]) scales the velocity limits, its square the acceleration limits: the
/// same trajectory 1 / speed times slower. Same errors ("path": fewer than
/// two configurations; "speed").
GraspTrajectory motionTrajectory(const std::vector<Eigen::VectorXd>& path,
                                 robot::CollisionChecker& checker, const MotionCheck& check,
                                 double rate, std::size_t* queries = nullptr,
                                 double maxDeviation = TrajectoryOptions{}.max_deviation,
                                 double speed = 1.0);

/// Appends `next`, which starts at rest where `trajectory` ends, to
/// `trajectory` (its samples after the first, their times shifted); returns
/// the time `next` starts at. Nothing is appended to an empty trajectory or
/// from an empty `next`: -1.
double appendTrajectory(GraspTrajectory& trajectory, const GraspTrajectory& next);

}  // namespace hfts::planner
