#include "planner/motion_goal.h"

#include <cmath>

#include "core/invalid_argument.h"
#include "robot/kinematics.h"

namespace hfts::planner {

namespace {

JointGoal checked(const robot::RobotModel& robot, const JointGoal& goal,
                  const Eigen::VectorXd& start, const std::string& field) {
  const Eigen::Index n = robot.numDofs(), arm = robot.numArmDofs();
  const Eigen::Index size = goal.configuration.size();
  if (size != n && size != arm)
    throw InvalidArgument(field, "needs " + std::to_string(n) + " values (every DoF) or " +
                                     std::to_string(arm) + " (the arm's), got " +
                                     std::to_string(size));
  JointGoal out{start};
  out.configuration.head(size) = goal.configuration;
  std::string why;
  if (!robot.withinLimits(out.configuration, 1e-9, &why)) throw InvalidArgument(field, why);
  return out;
}

PoseGoal checked(const robot::RobotModel& robot, const PoseGoal& goal, const std::string& field) {
  PoseGoal out = goal;
  const std::string& flange = robot.links()[static_cast<std::size_t>(robot.flangeLink())].name;
  const std::string& palm = robot.links()[static_cast<std::size_t>(robot.palmLink())].name;
  if (out.link.empty()) out.link = palm;
  if (out.link != flange && out.link != palm)
    throw InvalidArgument(field + ".link", "must be the flange link '" + flange +
                                               "' or the palm link '" + palm + "', got '" +
                                               out.link + "'");
  if (!out.pose.matrix().allFinite()) throw InvalidArgument(field + ".pose", "must be finite");
  const Eigen::Matrix3d r = out.pose.linear();
  if (!(r.transpose() * r).isIdentity(1e-6) || !(r.determinant() > 0.0))
    throw InvalidArgument(field + ".pose", "its orientation must be a rotation");
  if (!(out.position_tolerance >= 0.0 && out.position_tolerance <= kMaxPositionTolerance))
    throw InvalidArgument(field + ".position_tolerance",
                          "must be in [0, " + std::to_string(kMaxPositionTolerance) + "] m");
  if (!(out.orientation_tolerance >= 0.0 && out.orientation_tolerance <= kMaxOrientationTolerance))
    throw InvalidArgument(field + ".orientation_tolerance", "must be in [0, pi] rad");
  return out;
}

}  // namespace

std::vector<MotionGoal> checkGoals(const robot::RobotModel& robot,
                                   const std::vector<MotionGoal>& goals,
                                   const Eigen::VectorXd& start) {
  std::vector<MotionGoal> out;
  out.reserve(goals.size());
  for (std::size_t i = 0; i < goals.size(); ++i) {
    const std::string field = "goals[" + std::to_string(i) + "]";
    if (const auto* joint = std::get_if<JointGoal>(&goals[i]))
      out.emplace_back(checked(robot, *joint, start, field + ".joints"));
    else
      out.emplace_back(checked(robot, std::get<PoseGoal>(goals[i]), field));
  }
  return out;
}

bool satisfies(const robot::RobotModel& robot, const Eigen::Isometry3d& base,
               const MotionGoal& goal, const Eigen::VectorXd& q) {
  constexpr double kSlack = 1e-9;
  if (const auto* joint = std::get_if<JointGoal>(&goal))
    return joint->configuration.size() == q.size() &&
           ((joint->configuration - q).array().abs() <= kSlack).all();
  const auto& pose = std::get<PoseGoal>(goal);
  const robot::LinkPoses poses = robot::forwardKinematics(robot, q);
  const Eigen::Isometry3d at = base * poses[static_cast<std::size_t>(robot.linkIndex(pose.link))];
  const double distance = (at.translation() - pose.pose.translation()).norm();
  const double angle = Eigen::AngleAxisd(at.linear().transpose() * pose.pose.linear()).angle();
  return distance <= pose.position_tolerance + kSlack &&
         angle <= pose.orientation_tolerance + kSlack;
}

}  // namespace hfts::planner
