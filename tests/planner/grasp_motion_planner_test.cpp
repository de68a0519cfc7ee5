#include "planner/grasp_motion_planner.h"

#include <gtest/gtest.h>

#include "bundled_objects.h"
#include "planner/collision_checker.h"
#include "planner/kinematics.h"
#include "robot_fixture.h"

namespace hfts::planner {
namespace {

const PlanningWorld& world() {
  static const PlanningWorld w(test::kr5Sdh(), buildHandMap(test::kr5Sdh()),
                               test::bundledObjects());
  return w;
}

Scene bundledScene(const std::string& name) {
  return loadScene(test::sourcePath("objects/scenes/" + name + ".json"));
}

PlanRequest request(const std::string& scene, const std::string& object, std::uint64_t seed) {
  PlanRequest r;
  r.scene = bundledScene(scene);
  r.object = object;
  r.seed = seed;
  r.time_limit = 20.0;
  return r;
}

TEST(GraspMotionPlanner, PlansInTheTableScene) {
  const PlanResult result = planGrasp(world(), request("table", "mug", 1));
  ASSERT_TRUE(result.success) << result.message;
  std::printf("time %.3f s, GS %llu, VGS %llu, GNS %llu, checks %llu, waypoints %zu\n",
              result.stats.planning_time,
              static_cast<unsigned long long>(result.stats.goal_sampling_calls),
              static_cast<unsigned long long>(result.stats.valid_goal_samples),
              static_cast<unsigned long long>(result.stats.hfts_nodes_explored),
              static_cast<unsigned long long>(result.stats.collision_checks), result.path.size());
}

}  // namespace
}  // namespace hfts::planner
