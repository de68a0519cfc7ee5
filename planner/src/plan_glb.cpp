// planGlb (grasp_motion_planner.h): a plan result as robot::PlanAnimation.
#include "core/invalid_argument.h"
#include "planner/grasp_motion_planner.h"
#include "robot/kinematics.h"
#include "robot/plan_export.h"

namespace hfts::planner {

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
  // After the lift begins the object moves with the palm, as the hand
  // held it at the grasp (the path's last configuration).
  if (result.lift && !result.path.empty()) {
    const robot::RobotModel& robot = world.robot();
    const auto palm = [&](const Eigen::VectorXd& q) {
      return request.scene.robot_base *
             robot::forwardKinematics(robot, q)[static_cast<std::size_t>(robot.palmLink())];
    };
    const Eigen::Isometry3d inPalm = palm(result.path.back()).inverse() * result.object_pose;
    for (const TrajectoryPoint& p : result.trajectory.points)
      animation.object_motion.push_back(p.time > result.trajectory.lift_start
                                            ? Eigen::Isometry3d(palm(p.positions) * inPalm)
                                            : result.object_pose);
  }
  // The physics check's nominal trial, when the plan carries one.
  if (result.validation && result.validation->physics)
    for (const physics::MotionSample& m : result.validation->physics->nominal_motion) {
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
