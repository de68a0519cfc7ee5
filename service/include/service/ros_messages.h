#pragma once
// A plan in the shapes of the ROS messages a robot stack already speaks
// (docs/protocol.md and docs/python.md, "ROS-shaped results"): the grasp as a
// moveit_msgs/Grasp and the trajectory as a trajectory_msgs/JointTrajectory,
// as JSON objects with the messages' field names (ROS 1 layout, as
// rosbridge and genpy write them: durations and stamps {"secs", "nsecs"}).

#include <nlohmann/json_fwd.hpp>

#include <string>
#include <vector>

#include "planner/grasp_trajectory.h"
#include "planner/plan_request.h"
#include "planner/plan_result.h"
#include "planner/planning_world.h"

namespace hfts::service {

/// The frame every pose of the ROS-shaped results is in: the scene's world
/// frame (the one object_pose and the contacts are given in).
inline constexpr const char* kRosWorldFrame = "world";

/// trajectory_msgs/JointTrajectory of a planned trajectory: header (frame
/// kRosWorldFrame, stamp 0), joint_names, points with positions,
/// velocities, accelerations, an empty effort and time_from_start.
nlohmann::json rosJointTrajectory(const planner::GraspTrajectory& trajectory,
                                  const std::vector<std::string>& jointNames);

/// moveit_msgs/Grasp of a successful grasp plan: id (the object's name),
/// pre_grasp_posture (the hand's joints at the pre-grasp, time 0),
/// grasp_posture (closed on the contacts, at the end of the closing),
/// grasp_pose (the palm link at the grasp, world frame), grasp_quality
/// (epsilon at the contacts the closed hand touches), pre_grasp_approach
/// and post_grasp_retreat (distance 0: the planned path already ends at
/// the pre-grasp, and the planner plans no retreat; their directions are
/// the palm's approach axis and world up, for a stack that adds its own),
/// post_place_retreat (empty), max_contact_force 0 (no limit given) and
/// allowed_touch_objects (the object). Throws InvalidArgument ("plan") for
/// a failed plan or a motion plan.
nlohmann::json rosGrasp(const planner::PlanningWorld& world, const planner::PlanRequest& request,
                        const planner::PlanResult& result);

/// {"grasp": rosGrasp (null unless a successful grasp plan), "trajectory":
/// rosJointTrajectory (null without a trajectory)}: the `ros` member of a
/// `plan` result asked for with `format: "ros"`.
nlohmann::json rosPlan(const planner::PlanningWorld& world, const planner::PlanRequest& request,
                       const planner::PlanResult& result);

}  // namespace hfts::service
