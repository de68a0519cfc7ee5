#include "planner/lazy_goal_baseline.h"

#include <gtest/gtest.h>

#include <chrono>

#include "core/invalid_argument.h"
#include "plan_checks.h"
#include "planner/multi_tree_cbirrt.h"
#include "test_meshes.h"

namespace hfts::planner {
namespace {

using test::kFinalResolution;

const PlanningWorld& world() {
  return test::bundledWorld();
}

PlanRequest request(const std::string& scene, const std::string& object, std::uint64_t seed) {
  return test::bundledSceneRequest(scene, object, seed, PlanAlgorithm::kRrtConnect);
}

double secondsSince(std::chrono::steady_clock::time_point began) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
}

class RrtConnectInBundledScenes : public ::testing::TestWithParam<test::SceneObject> {};

TEST_P(RrtConnectInBundledScenes, PathsAreFreeAndEndInAStableGrasp) {
  for (std::uint64_t seed = 1; seed <= 2; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const PlanRequest r = request(GetParam().scene, GetParam().object, seed);
    const PlanResult result = planGrasp(world(), r);
    test::expectValidPlan(world(), r, result, kFinalResolution);
    const PlanStatistics& s = result.stats;
    EXPECT_GE(s.goal_sampling_calls, s.valid_goal_samples);
    EXPECT_GE(s.valid_goal_samples, 1u);
    EXPECT_GE(s.hfts_nodes_explored, 1u);
    EXPECT_GE(s.goal_trees, 1u);
    EXPECT_GT(s.iterations, 0u);
    EXPECT_GT(s.collision_checks, 0u);
    EXPECT_LE(s.path_length_smoothed, s.path_length_raw + 1e-9);
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, RrtConnectInBundledScenes,
                         ::testing::Values(test::SceneObject{"table", "mug"},
                                           test::SceneObject{"bin", "blob"}),
                         test::sceneObjectName);

TEST(LazyGoalRrtConnect, HonoursTheTimeLimitAndJoinsTheSamplingThread) {
  // No grasp can be a goal with a 1e-9 m fingertip tolerance: the sampling
  // thread searches until it is stopped at the limit.
  PlanRequest r = request("table", "mug", 1);
  r.time_limit = 0.3;
  r.parameters["max_fingertip_error"] = "1e-9";
  world();  // built first: building it leaves worker threads behind and takes a second
  const int threads = test::processThreadCount();
  const auto began = std::chrono::steady_clock::now();
  const PlanResult result = planGrasp(world(), r);
  const double elapsed = secondsSince(began);
  EXPECT_FALSE(result.success);
  EXPECT_EQ(result.failure, PlanFailure::kNoValidGoal);
  EXPECT_GE(elapsed, searchTimeLimit(0.3));
  EXPECT_LT(elapsed, 0.3 + 0.5);  // generous for a loaded test machine
  EXPECT_GT(result.stats.goal_sampling_calls, 0u);
  EXPECT_EQ(result.stats.valid_goal_samples, 0u);
  // Stable grasps with an arm IK solution are rejected for the hand's reach.
  EXPECT_GT(result.stats.rejected.out_of_hand_reach, 0u);
  EXPECT_EQ(result.stats.rejected.colliding + result.stats.rejected.closing_blocked, 0u);
  EXPECT_NE(result.message.find("out of the hand's reach"), std::string::npos) << result.message;
  EXPECT_EQ(test::processThreadCount(), threads);
}

TEST(LazyGoalRrtConnect, CancellationStopsBothThreads) {
  std::atomic<bool> cancel{true};
  world();  // built first: building it leaves worker threads behind and takes a second
  const int threads = test::processThreadCount();
  const auto began = std::chrono::steady_clock::now();
  const PlanResult result = planGrasp(world(), request("table", "mug", 1), &cancel);
  EXPECT_LT(secondsSince(began), 1.0);
  EXPECT_FALSE(result.success);
  EXPECT_EQ(result.failure, PlanFailure::kCancelled);
  EXPECT_EQ(test::processThreadCount(), threads);
}

TEST(LazyGoalRrtConnect, UnreachableObjectIsReported) {
  const PlanResult result =
      planGrasp(world(), test::justOutOfReachRequest(PlanAlgorithm::kRrtConnect));
  EXPECT_FALSE(result.success);
  EXPECT_EQ(result.failure, PlanFailure::kObjectUnreachable) << result.message;
}

TEST(LazyGoalRrtConnect, RejectsIterationsBelowOne) {
  const robot::Scene scene = robot::loadScene(test::sourcePath("objects/scenes/table.json"));
  const db::ObjectDatabase& mug = *world().object("mug");
  robot::CollisionChecker checker(world().collisionModel(), scene, &mug.geometry);
  const grasp::HftsSpace space(mug, static_cast<int>(world().robot().fingertips().size()));
  LazyGoalSettings settings;
  settings.goals.decoupled_iterations = 0;
  test::expectErrorMentioning<InvalidArgument>(
      [&] {
        LazyGoalRrtConnect(makeSpaceInformation(world().robot(), checker, 0.02), world(), scene,
                           mug, space, settings);
      },
      {"parameters.iterations: must be >= 1"});
}

TEST(LazyGoalRrtConnect, ReadsTheSharedParameters) {
  // The baseline takes i, smoothing and the time limit from the same
  // parameter names as the multi-tree planner.
  PlanRequest r = request("bin", "blob", 3);
  r.iterations = 60;
  r.parameters["smoothing_steps"] = "0";
  const PlanResult result = planGrasp(world(), r);
  test::expectValidPlan(world(), r, result, kFinalResolution);
  EXPECT_DOUBLE_EQ(result.stats.path_length_smoothed, result.stats.path_length_raw);
  r.parameters["kappa"] = "many";  // validated like every parameter, used or not
  test::expectErrorMentioning<InvalidArgument>([&] { planGrasp(world(), r); },
                                               {"parameters.kappa: must be an integer"});
}

}  // namespace
}  // namespace hfts::planner
