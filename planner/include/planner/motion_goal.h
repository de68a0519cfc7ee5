#pragma once
// Motion-only goals (docs/planning.md "Motion-only goals"): a joint-space
// configuration or an end-effector pose with tolerances. A plan request
// with goals plans a path to whichever of them the multi-tree planner
// reaches first, with no grasp.

#include <Eigen/Geometry>

#include <string>
#include <variant>
#include <vector>

#include "robot/robot_model.h"

namespace hfts::planner {

/// A configuration to reach: every DoF (numDofs() values), or the arm's
/// only (numArmDofs() values; the hand keeps the start's posture).
struct JointGoal {
  Eigen::VectorXd configuration;
};

/// A pose of the robot's flange or palm link to reach, in the world frame:
/// its origin within `position_tolerance` (m) of `pose`'s and its
/// orientation within `orientation_tolerance` (rad, the angle of the
/// rotation between them). The hand keeps the start's posture.
struct PoseGoal {
  std::string link;  ///< the config's flange_link or palm_link; empty: palm_link
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  double position_tolerance = 0.001;
  double orientation_tolerance = 0.01;
};

using MotionGoal = std::variant<JointGoal, PoseGoal>;

/// The largest tolerances a pose goal may ask for (m, rad).
inline constexpr double kMaxPositionTolerance = 0.5;
inline constexpr double kMaxOrientationTolerance = 3.14159265358979323846;

/// `goals` checked for `robot` and completed: joint goals of the arm only
/// get `start`'s hand posture, a pose goal's empty link becomes the palm
/// link. Throws InvalidArgument naming the field ("goals", "goals[i].joints",
/// "goals[i].link", "goals[i].pose", "goals[i].position_tolerance",
/// "goals[i].orientation_tolerance"): a joint goal of another size, not
/// finite or outside the joint limits; a link that is neither the flange
/// nor the palm; a pose that is not finite or whose rotation is not one; a
/// tolerance outside [0, kMax...Tolerance].
std::vector<MotionGoal> checkGoals(const robot::RobotModel& robot,
                                   const std::vector<MotionGoal>& goals,
                                   const Eigen::VectorXd& start);

/// Whether configuration `q` (numDofs() values) satisfies `goal` (checked
/// by checkGoals) with the robot's base at `base`: a joint goal within
/// 1e-9 rad in every DoF, a pose goal within its tolerances (plus 1e-9).
bool satisfies(const robot::RobotModel& robot, const Eigen::Isometry3d& base,
               const MotionGoal& goal, const Eigen::VectorXd& q);

}  // namespace hfts::planner
