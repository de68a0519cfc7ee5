#include "planner/grasp_motion_planner.h"

#include <gtest/gtest.h>

#include <chrono>

#include "bundled_objects.h"
#include "planner/collision_checker.h"
#include "planner/grasp_quality.h"
#include "planner/kinematics.h"
#include "robot_fixture.h"
#include "test_meshes.h"

namespace hfts::planner {
namespace {

constexpr double kFinalResolution = 0.0025;  // the planner's final_resolution default

const PlanningWorld& world() {
  static const PlanningWorld w(test::kr5Sdh(), buildHandMap(test::kr5Sdh()),
                               test::bundledObjects());
  return w;
}

PlanRequest request(const std::string& scene, const std::string& object, std::uint64_t seed,
                    PlanAlgorithm algorithm = PlanAlgorithm::kCoupled) {
  PlanRequest r;
  r.scene = loadScene(test::sourcePath("objects/scenes/" + scene + ".json"));
  r.object = object;
  r.seed = seed;
  r.algorithm = algorithm;
  r.time_limit = 30.0;
  return r;
}

/// Everything a returned plan promises, checked independently of the
/// planner: a fresh collision checker at the planner's final resolution
/// (what it promises; a graze shallower than a sample step can hide
/// between samples at any resolution, see docs/planning.md), the start,
/// the grasp and its quality.
void expectValidPlan(const PlanRequest& r, const PlanResult& result) {
  ASSERT_TRUE(result.success) << result.message;
  const RobotModel& robot = world().robot();
  const db::ObjectDatabase& object = *world().object(r.object);
  Scene scene = r.scene;
  scene.target_object = r.object;
  CollisionChecker checker(robot, scene, &object.geometry);
  ASSERT_GE(result.path.size(), 2u);
  EXPECT_EQ(result.joint_names, robot.dofNames());
  EXPECT_TRUE(result.path.front().isApprox(scene.start.value_or(robot.home()), 1e-12));
  for (const Eigen::VectorXd& q : result.path) EXPECT_TRUE(robot.withinLimits(q));
  for (std::size_t i = 1; i + 1 < result.path.size(); ++i)
    EXPECT_TRUE(checker.isMotionValid(result.path[i - 1], result.path[i], kFinalResolution))
        << "segment " << i << " collides";
  const Eigen::VectorXd& pregrasp = result.path[result.path.size() - 2];
  const Eigen::VectorXd& grasp = result.path.back();
  EXPECT_TRUE(
      checker.isMotionValid(pregrasp, grasp, kFinalResolution, /*allowFingertipContact=*/true));
  EXPECT_TRUE(grasp.tail(robot.numHandDofs()).isApprox(result.grasp.hand_configuration));

  // Fingertips on the contacts (some finger per contact) within 5 mm.
  const FingertipFrames tips = fingertipFrames(robot, forwardKinematics(robot, grasp));
  const Eigen::Matrix3Xd contacts = scene.robot_base.inverse() * result.grasp.contacts_world;
  for (Eigen::Index c = 0; c < contacts.cols(); ++c) {
    double nearest = 1e9;
    for (Eigen::Index f = 0; f < tips.positions.cols(); ++f)
      nearest = std::min(nearest, (tips.positions.col(f) - contacts.col(c)).norm());
    EXPECT_LT(nearest, 0.005) << "contact " << c;
  }
  // A stable grasp: epsilon recomputed from the world-frame contacts.
  GraspQualityRequest q;
  q.positions = result.grasp.contacts_world;
  q.normals = result.grasp.inward_normals_world;
  q.center = r.object_pose.value_or(scene.target_pose) * object.geometry.center_of_mass;
  q.torque_scale = object.geometry.rho;
  const double epsilon = graspQuality(q).epsilon;
  EXPECT_GT(epsilon, 0.0);
  EXPECT_NEAR(epsilon, result.grasp.epsilon, 1e-9);
}

struct Case {
  const char* scene;
  const char* object;
};

class PlansInBundledScenes : public ::testing::TestWithParam<Case> {};

TEST_P(PlansInBundledScenes, PathsAreFreeAndEndInAStableGrasp) {
  for (std::uint64_t seed = 1; seed <= 2; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const PlanRequest r = request(GetParam().scene, GetParam().object, seed);
    expectValidPlan(r, planGrasp(world(), r));
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, PlansInBundledScenes,
                         ::testing::Values(Case{"table", "mug"}, Case{"table", "box"},
                                           Case{"shelf", "bottle"}, Case{"shelf", "mug"},
                                           Case{"bin", "blob"}, Case{"bin", "cylinder"}),
                         [](const ::testing::TestParamInfo<Case>& param) {
                           return std::string(param.param.scene) + "_" + param.param.object;
                         });

TEST(GraspMotionPlanner, DecoupledBaselinePlansToo) {
  PlanRequest r = request("table", "mug", 3, PlanAlgorithm::kDecoupled);
  r.iterations = 20;
  expectValidPlan(r, planGrasp(world(), r));
}

TEST(GraspMotionPlanner, SameSeedGivesTheSamePath) {
  const PlanRequest r = request("bin", "blob", 5);
  const PlanResult a = planGrasp(world(), r);
  const PlanResult b = planGrasp(world(), r);
  ASSERT_TRUE(a.success && b.success);
  ASSERT_EQ(a.path.size(), b.path.size());
  for (std::size_t i = 0; i < a.path.size(); ++i) EXPECT_EQ(a.path[i], b.path[i]);
  EXPECT_EQ(a.grasp.node, b.grasp.node);
  EXPECT_EQ(a.stats.iterations, b.stats.iterations);
  EXPECT_EQ(a.stats.collision_checks, b.stats.collision_checks);
}

TEST(GraspMotionPlanner, HonoursTheTimeLimit) {
  // Without goal sampling no plan can succeed: the planner must give up at
  // the limit.
  PlanRequest r = request("table", "mug", 1);
  r.time_limit = 0.3;
  r.parameters["p_max"] = "0";
  r.parameters["p_min"] = "0";
  world();  // built before the clock starts
  const auto began = std::chrono::steady_clock::now();
  const PlanResult result = planGrasp(world(), r);
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  EXPECT_FALSE(result.success);
  EXPECT_EQ(result.failure, PlanFailure::kTimeLimit);
  EXPECT_GE(elapsed, 0.3);
  // Generous bound for a loaded test machine; hfts-bench measures the
  // real overshoot (docs/performance.md).
  EXPECT_LT(elapsed, 0.3 + 0.5);
}

TEST(GraspMotionPlanner, CancellationStopsThePlanner) {
  std::atomic<bool> cancel{true};
  const PlanResult result = planGrasp(world(), request("table", "mug", 1), &cancel);
  EXPECT_FALSE(result.success);
  EXPECT_EQ(result.failure, PlanFailure::kCancelled);
}

TEST(GraspMotionPlanner, StartInCollisionIsReported) {
  PlanRequest r = request("table", "mug", 1);
  // Shoulder forward and down: the arm goes through the table.
  r.start = (Eigen::VectorXd(13) << 0, 0.6, 0.5, 0, 1.57, 0, 0, -0.2, 0.2, -0.2, 0.2, -0.2, 0.2)
                .finished();
  const PlanResult result = planGrasp(world(), r);
  EXPECT_FALSE(result.success);
  EXPECT_EQ(result.failure, PlanFailure::kStartInCollision);
  EXPECT_NE(result.message.find("table"), std::string::npos) << result.message;
}

TEST(GraspMotionPlanner, UnknownObjectIsReported) {
  const PlanResult result = planGrasp(world(), request("table", "teapot", 1));
  EXPECT_FALSE(result.success);
  EXPECT_EQ(result.failure, PlanFailure::kUnknownObject);
  EXPECT_NE(result.message.find("teapot"), std::string::npos);
}

TEST(GraspMotionPlanner, UnreachableObjectIsReported) {
  PlanRequest r = request("table", "mug", 1);
  r.scene.obstacles.clear();
  r.object_pose = Eigen::Isometry3d(Eigen::Translation3d(3.0, 0.0, 0.0));
  r.time_limit = 1.0;
  const PlanResult result = planGrasp(world(), r);
  EXPECT_FALSE(result.success);
  EXPECT_EQ(result.failure, PlanFailure::kObjectUnreachable) << result.message;
}

TEST(GraspMotionPlanner, MalformedRequestsThrowNamingTheField) {
  PlanRequest r = request("table", "mug", 1);
  r.start = Eigen::VectorXd::Zero(5);
  test::expectErrorMentioning<std::invalid_argument>([&] { planGrasp(world(), r); }, {"start"});
  r.start = world().robot().home();
  (*r.start)(0) = 10.0;
  test::expectErrorMentioning<std::invalid_argument>([&] { planGrasp(world(), r); }, {"a1"});
  r.start.reset();
  r.parameters["no_such"] = "1";
  test::expectErrorMentioning<std::invalid_argument>([&] { planGrasp(world(), r); }, {"no_such"});
  r.parameters = {{"p_max", "2"}};
  test::expectErrorMentioning<std::invalid_argument>([&] { planGrasp(world(), r); }, {"p_max"});
  r.parameters = {{"kappa", "many"}};
  test::expectErrorMentioning<std::invalid_argument>([&] { planGrasp(world(), r); }, {"kappa"});
  r.parameters.clear();
  r.iterations = 0;
  test::expectErrorMentioning<std::invalid_argument>([&] { planGrasp(world(), r); },
                                                     {"iterations"});
}

TEST(GraspMotionPlanner, DeclaresThePaperParametersWithTheirDefaults) {
  std::map<std::string, double> expected = {
      {"p_max", 0.9},       {"p_goal_tree", 0.7}, {"p_min", 0.01},     {"d_m", 0.4},
      {"w_f", 0.5},         {"n_a", 20},          {"w_c", 4.0},        {"alpha", 1e-6},
      {"kappa", 4},         {"p_w", 1.2},         {"weight_arm", 1.0}, {"weight_hand", 0.25},
      {"i_min", 20},        {"i_max", 100},       {"friction", 0.5},   {"cone_edges", 8},
      {"time_limit", 60.0}, {"step_size", 0.1}};
  for (const PlannerParameterInfo& p : plannerParameters(world())) {
    const auto it = expected.find(p.name);
    if (it == expected.end()) continue;
    EXPECT_NEAR(std::stod(p.default_value), it->second, 1e-12 + 1e-9 * it->second) << p.name;
    expected.erase(it);
  }
  for (const auto& [name, value] : expected) ADD_FAILURE() << "not declared: " << name;
}

}  // namespace
}  // namespace hfts::planner
