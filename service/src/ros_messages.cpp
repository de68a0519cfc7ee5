#include "service/ros_messages.h"

#include <nlohmann/json.hpp>

#include <cmath>

#include "core/invalid_argument.h"
#include "robot/kinematics.h"

namespace hfts::service {
namespace {

using nlohmann::json;

/// builtin Duration / Time {secs, nsecs} of `seconds` (>= 0), rounded to
/// the nanosecond.
json rosDuration(double seconds) {
  const auto total = static_cast<long long>(std::llround(seconds * 1e9));
  return {{"secs", total / 1000000000LL}, {"nsecs", total % 1000000000LL}};
}

json rosHeader(const std::string& frame) {
  return {{"seq", 0}, {"stamp", rosDuration(0.0)}, {"frame_id", frame}};
}

json rosVector(const Eigen::Vector3d& v) {
  return {{"x", v.x()}, {"y", v.y()}, {"z", v.z()}};
}

json rosPose(const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond q(pose.linear());
  return {{"position", rosVector(pose.translation())},
          {"orientation", {{"x", q.x()}, {"y", q.y()}, {"z", q.z()}, {"w", q.w()}}}};
}

std::vector<double> values(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

/// A JointTrajectory of one point: the hand's joints at `positions`, at
/// rest, at `time`.
json handPosture(const std::vector<std::string>& handJoints, const Eigen::VectorXd& positions,
                 double time) {
  const std::vector<double> zero(static_cast<std::size_t>(positions.size()), 0.0);
  return {{"header", rosHeader(kRosWorldFrame)},
          {"joint_names", handJoints},
          {"points", json::array({{{"positions", values(positions)},
                                   {"velocities", zero},
                                   {"accelerations", zero},
                                   {"effort", json::array()},
                                   {"time_from_start", rosDuration(time)}}})}};
}

json gripperTranslation(const std::string& frame, const Eigen::Vector3d& direction) {
  return {{"direction", {{"header", rosHeader(frame)}, {"vector", rosVector(direction)}}},
          {"desired_distance", 0.0},
          {"min_distance", 0.0}};
}

}  // namespace

json rosJointTrajectory(const planner::GraspTrajectory& trajectory,
                        const std::vector<std::string>& jointNames) {
  json points = json::array();
  for (const planner::TrajectoryPoint& p : trajectory.points)
    points.push_back({{"positions", values(p.positions)},
                      {"velocities", values(p.velocities)},
                      {"accelerations", values(p.accelerations)},
                      {"effort", json::array()},
                      {"time_from_start", rosDuration(p.time)}});
  return {{"header", rosHeader(kRosWorldFrame)},
          {"joint_names", jointNames},
          {"points", std::move(points)}};
}

json rosGrasp(const planner::PlanningWorld& world, const planner::PlanRequest& request,
              const planner::PlanResult& result) {
  if (!result.success || !request.goals.empty() || result.path.size() < 2)
    throw InvalidArgument("plan", "a ROS grasp needs a successful grasp plan");
  const robot::RobotModel& robot = world.robot();
  const auto handDofs = static_cast<std::ptrdiff_t>(robot.numHandDofs());
  const std::vector<std::string> handJoints(robot.dofNames().end() - handDofs,
                                            robot.dofNames().end());
  const Eigen::VectorXd& pregrasp = result.path[result.path.size() - 2];
  const Eigen::VectorXd& grasp = result.path.back();
  const Eigen::Isometry3d palm =
      request.scene.robot_base *
      robot::forwardKinematics(robot, grasp)[static_cast<std::size_t>(robot.palmLink())];
  // The palm approaches along the line from its origin to the contacts'
  // centroid (palm frame).
  const Eigen::Vector3d centroid = result.grasp.contacts_world.rowwise().mean();
  Eigen::Vector3d approach = palm.inverse() * centroid;
  approach = approach.norm() > 1e-9 ? approach.normalized() : Eigen::Vector3d::UnitZ();
  const double closing = result.trajectory.points.empty()
                             ? 0.0
                             : result.trajectory.duration - result.trajectory.closing_start;
  const std::string palmFrame = robot.links()[static_cast<std::size_t>(robot.palmLink())].name;
  return {{"id", request.object},
          {"pre_grasp_posture", handPosture(handJoints, pregrasp.tail(handDofs), 0.0)},
          {"grasp_posture", handPosture(handJoints, grasp.tail(handDofs), closing)},
          {"grasp_pose", {{"header", rosHeader(kRosWorldFrame)}, {"pose", rosPose(palm)}}},
          {"grasp_quality", result.grasp.epsilon},
          {"pre_grasp_approach", gripperTranslation(palmFrame, approach)},
          {"post_grasp_retreat", gripperTranslation(kRosWorldFrame, Eigen::Vector3d::UnitZ())},
          {"post_place_retreat", gripperTranslation(kRosWorldFrame, Eigen::Vector3d::Zero())},
          {"max_contact_force", 0.0},
          {"allowed_touch_objects", json::array({request.object})}};
}

json rosPlan(const planner::PlanningWorld& world, const planner::PlanRequest& request,
             const planner::PlanResult& result) {
  const bool grasp = result.success && request.goals.empty() && result.path.size() >= 2;
  return {{"grasp", grasp ? rosGrasp(world, request, result) : json()},
          {"trajectory", result.trajectory.points.empty()
                             ? json()
                             : rosJointTrajectory(result.trajectory, result.joint_names)}};
}

}  // namespace hfts::service
