// planGlb (grasp_motion_planner.h): a plan result as robot::PlanAnimation.
#include "core/invalid_argument.h"
#include "planner/grasp_motion_planner.h"
#include "robot/kinematics.h"
#include "robot/plan_export.h"

namespace hfts::planner {

std::vector<Eigen::Isometry3d> objectAlongTrajectory(const PlanningWorld& world,
                                                     const PlanRequest& request,
                                                     const PlanResult& result) {
  const GraspTrajectory& t = result.trajectory;
  if (!result.lift || result.path.empty() || t.points.empty())
    throw InvalidArgument("plan", "only a plan with a lift and a trajectory carries its object");
  const robot::RobotModel& robot = world.robot();
  const auto palm = [&](const Eigen::VectorXd& q) {
    return request.scene.robot_base *
           robot::forwardKinematics(robot, q)[static_cast<std::size_t>(robot.palmLink())];
  };
  // Held as the hand held it at the grasp (the path's last configuration).
  const Eigen::Isometry3d inPalm = palm(result.path.back()).inverse() * result.object_pose;
  std::vector<Eigen::Isometry3d> poses;
  poses.reserve(t.points.size());
  for (const TrajectoryPoint& p : t.points) {
    if (p.time <= t.lift_start)
      poses.push_back(result.object_pose);
    else if (result.place && p.time >= t.release_start)
      poses.push_back(result.place->object_pose);
    else
      poses.emplace_back(palm(p.positions) * inPalm);
  }
  return poses;
}

std::string planGlb(const PlanningWorld& world, const PlanRequest& request,
                    const PlanResult& result) {
  if (result.trajectory.points.empty())
    throw InvalidArgument("trajectory", "the plan has none to animate");
  robot::PlanAnimation animation;
  for (const TrajectoryPoint& p : result.trajectory.points) {
    animation.times.push_back(p.time);
    animation.configurations.push_back(p.positions);
  }
  animation.object_pose = result.object_pose;
  animation.contacts = result.grasp.contacts_world;
  animation.inward_normals = result.grasp.inward_normals_world;
  animation.path = result.path;
  if (result.lift)
    for (const Eigen::Isometry3d& pose : objectAlongTrajectory(world, request, result))
      animation.object_motion.push_back(pose);
  // The physics check's nominal trial, when the plan carries one: the
  // whole pick and place's when it has one.
  const std::vector<physics::MotionSample>* simulated = nullptr;
  if (result.validation && result.validation->physics)
    simulated = &result.validation->physics->nominal_motion;
  if (result.validation && result.validation->place) simulated = &result.validation->place->motion;
  if (simulated != nullptr)
    for (const physics::MotionSample& m : *simulated) {
      if (!animation.simulated_times.empty() && !(m.time > animation.simulated_times.back()))
        continue;
      animation.simulated_times.push_back(m.time);
      animation.simulated_configurations.push_back(m.configuration);
      animation.simulated_object.push_back(m.object);
    }
  robot::Scene scene = request.scene;
  scene.target_object = request.object.empty() ? request.scene.target_object : request.object;
  const db::ObjectDatabase* object = world.object(scene.target_object);
  return robot::planGlb(world.robot(), scene, object != nullptr ? &object->geometry : nullptr,
                        animation);
}

}  // namespace hfts::planner
