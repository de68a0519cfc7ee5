#pragma once
// The arm motion that lifts a grasped object: joint-space waypoints that
// move the palm along a straight line with its orientation kept, from
// damped-least-squares steps on the robot's Jacobian.

#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "hfts_db/object_database.h"
#include "robot/collision_model.h"
#include "robot/robot_model.h"
#include "robot/scene.h"

namespace hfts::physics {

/// A straight palm path in joint space.
struct PalmLine {
  /// Full configurations (numDofs values; the hand as in the start), the
  /// start first, one per `step` of palm travel, the last at `distance`.
  std::vector<Eigen::VectorXd> waypoints;
  /// Empty when the palm reached `distance`; else why not (the waypoints
  /// then end where it got to).
  std::string problem;
};

/// Moves the palm from where `start` puts it by `distance` (m) along
/// `direction` (world frame, any length > 0) in steps of `step` (m), keeping
/// its orientation: each waypoint by damped least squares on the arm's
/// Jacobian from the previous one, converged to 1e-6 m and 1e-5 rad, within
/// the joint limits. `robotBase` is the base link in the world. Throws
/// InvalidArgument ("start", "direction", "distance", "step") for a start
/// of the wrong size or outside the limits, a zero direction or
/// non-positive lengths.
PalmLine straightPalmLine(const robot::RobotModel& robot, const Eigen::Isometry3d& robotBase,
                          const Eigen::VectorXd& start, const Eigen::Vector3d& direction,
                          double distance, double step = 0.005);

/// The lift of a grasp: the first of these palm lines that is complete
/// and collision-free for the robot in the scene without the object (the
/// hand at `grasp`; robot::CollisionChecker) and, when the object is given,
/// for the object carried along it: world up; straight back against the
/// palm's approach axis (its -z, which points out of the hand towards the
/// fingers for every bundled hand); up at 45 degrees towards that retreat,
/// towards the robot's base, or towards +-x, +-y of the world. None: world
/// up regardless ("up_blocked").
struct LiftPlan {
  /// "up", "retreat", "up_retreat", "up_to_base", "up_x", "up_minus_x",
  /// "up_y", "up_minus_y" or "up_blocked"
  std::string direction;
  PalmLine line;
  std::string blocked_by;  ///< for "up_blocked": why up was refused
};

/// Plans the lift of `height` (m) from `grasp` (a full configuration), the
/// object (may be null: not checked) at scene.target_pose; the robot is
/// `model`'s. Throws as straightPalmLine.
LiftPlan planLift(const robot::CollisionModel& model, const robot::Scene& scene,
                  const Eigen::VectorXd& grasp, double height,
                  const db::ObjectGeometry* object = nullptr);

}  // namespace hfts::physics
