// planGlb (grasp_motion_planner.h): a plan result as robot::PlanAnimation.
#include "hfts_db/invalid_argument.h"
#include "planner/grasp_motion_planner.h"
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
  robot::Scene scene = request.scene;
  scene.target_object = request.object.empty() ? request.scene.target_object : request.object;
  const db::ObjectDatabase* object = world.object(scene.target_object);
  return robot::planGlb(world.robot(), scene, object != nullptr ? &object->geometry : nullptr,
                        animation);
}

}  // namespace hfts::planner
