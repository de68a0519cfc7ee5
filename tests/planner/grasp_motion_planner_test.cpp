#include "planner/grasp_motion_planner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/invalid_argument.h"
#include "planner/lift.h"
#include "planner/parameters.h"
#include "robot/kinematics.h"
#include "robot/segment_certificate.h"

#include "grasp/hand_map_builder.h"
#include "grasp/hand_reachability.h"
#include "holdability.h"
#include "plan_checks.h"
#include "robot_fixture.h"
#include "test_meshes.h"

namespace hfts::planner {
namespace {

using bench::Holdability;
using bench::holdability;

const PlanningWorld& world() {
  return test::bundledWorld();
}

PlanRequest request(const std::string& scene, const std::string& object, std::uint64_t seed,
                    PlanAlgorithm algorithm = PlanAlgorithm::kCoupled) {
  return test::bundledSceneRequest(scene, object, seed, algorithm);
}

void expectValidPlan(const PlanRequest& r, const PlanResult& result) {
  test::expectValidPlan(world(), r, result, test::kFinalResolution);
}

class PlansInBundledScenes : public ::testing::TestWithParam<test::SceneObject> {};

TEST_P(PlansInBundledScenes, PathsAreFreeAndEndInAStableGrasp) {
  for (std::uint64_t seed = 1; seed <= 2; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    // The paths and the grasp's checks, without the physics check (seconds
    // per goal; whether plans hold: ByDefaultEveryPlanIsAGraspThatHeldInPhysics
    // and docs/experiments/2026-11-27-physics-check.md).
    PlanRequest r = request(GetParam().scene, GetParam().object, seed);
    r.parameters["physics_check"] = "0";
    expectValidPlan(r, planGrasp(world(), r));
  }
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, PlansInBundledScenes,
    ::testing::Values(test::SceneObject{"table", "mug"}, test::SceneObject{"table", "box"},
                      test::SceneObject{"shelf", "bottle"}, test::SceneObject{"shelf", "mug"},
                      test::SceneObject{"bin", "blob"}, test::SceneObject{"bin", "cylinder"}),
    test::sceneObjectName);

TEST(GraspMotionPlanner, CertifiedPathsAreFreeByADenseDistanceSweep) {
  // With certify_path every motion of the plan is proven: an independent
  // FCL distance sweep (the robot to the environment and to itself at 401
  // states per segment) finds every state of the path to the pre-grasp
  // free, the reported clearance is a distance the sweep does not beat by
  // more than its step; the closing is proven under its rule (fingertips
  // on the object), and refused when a fingertip ends in an obstacle.
  PlanRequest r = request("table", "mug", 1);
  r.parameters["physics_check"] = "0";
  r.parameters["certify_path"] = "1";
  const PlanResult result = planGrasp(world(), r);
  expectValidPlan(r, result);
  ASSERT_TRUE(result.clearance.has_value());
  EXPECT_GT(*result.clearance, 0.0);
  EXPECT_GT(result.stats.certificate_queries, 0u);
  EXPECT_FALSE(result.trajectory.points.empty());
  const robot::Scene scene = test::plannedScene(world(), r);
  robot::CollisionChecker checker(world().collisionModel(), scene,
                                  &world().object(scene.target_object)->geometry);
  double swept = 1e9;
  for (std::size_t i = 1; i + 1 < result.path.size(); ++i)
    for (int k = 0; k <= 400; ++k) {
      const Eigen::VectorXd q =
          result.path[i - 1] + (result.path[i] - result.path[i - 1]) * (k / 400.0);
      const double d = checker.clearance(q);
      swept = std::min(swept, d > 0.0 ? std::min(d, checker.selfClearance(q)) : 0.0);
    }
  EXPECT_GT(swept, 0.0);
  const Eigen::VectorXd& pregrasp = result.path[result.path.size() - 2];
  robot::CertifyOptions closing;
  closing.rule = robot::CertifyRule::kClosing;
  EXPECT_TRUE(
      robot::certifySegment(checker, world().motionBound(), pregrasp, result.path.back(), closing)
          .free);
  // A fingertip may touch the object, not an obstacle: a 3 mm ball where
  // the first fingertip ends up is refused.
  robot::Scene blocked = scene;
  robot::Obstacle ball;
  ball.name = "ball";
  ball.type = robot::Obstacle::Type::kSphere;
  ball.size = Eigen::Vector3d::Constant(0.003);
  ball.pose =
      scene.robot_base *
      robot::forwardKinematics(
          world().robot(),
          result.path.back())[static_cast<std::size_t>(world().robot().fingertips()[0].link)];
  blocked.obstacles.push_back(ball);
  robot::CollisionChecker blockedChecker(world().collisionModel(), blocked,
                                         &world().object(scene.target_object)->geometry);
  EXPECT_FALSE(robot::certifySegment(blockedChecker, world().motionBound(), pregrasp,
                                     result.path.back(), closing)
                   .free);
  // The trajectory's chords, proven as one polyline under the approach rule.
  std::vector<Eigen::VectorXd> approach;
  for (const TrajectoryPoint& p : result.trajectory.points)
    if (p.time <= result.trajectory.closing_start) approach.push_back(p.positions);
  robot::CertifyOptions arriving;
  arriving.rule = robot::CertifyRule::kApproach;
  EXPECT_TRUE(robot::certifyPath(checker, world().motionBound(), approach, arriving).free);
}

TEST(GraspMotionPlanner, DecoupledBaselinePlansToo) {
  PlanRequest r = request("table", "mug", 3, PlanAlgorithm::kDecoupled);
  r.iterations = 20;
  r.parameters["physics_check"] = "0";  // the decoupled search, not whether it holds
  expectValidPlan(r, planGrasp(world(), r));
}

TEST(GraspMotionPlanner, ExploredNodesAreTheCachedNodesOnTheObjectsContacts) {
  PlanRequest r = request("bin", "blob", 5);
  r.parameters["physics_check"] = "0";  // the cache's nodes, not whether they hold
  const PlanResult quiet = planGrasp(world(), r);
  ASSERT_TRUE(quiet.success) << quiet.message;
  EXPECT_TRUE(quiet.explored.empty()) << "only when asked";
  r.explored = true;
  const PlanResult result = planGrasp(world(), r);
  ASSERT_TRUE(result.success) << result.message;
  EXPECT_EQ(result.explored.size(), result.stats.hfts_nodes_explored);
  const db::ObjectDatabase& blob = *world().object("blob");
  bool someGoal = false;
  for (const ExploredNode& n : result.explored) {
    EXPECT_GE(n.level, 1);
    EXPECT_LE(n.level, 3);
    ASSERT_EQ(n.contacts_object.cols(), 3);
    for (Eigen::Index c = 0; c < 3; ++c) {
      const Eigen::Vector3d p = n.contacts_object.col(c);
      const double nearest = (blob.positions.rowwise() - p.transpose()).rowwise().norm().minCoeff();
      EXPECT_LT(nearest, 1e-12) << "a representative is one of the object's contacts";
    }
    EXPECT_GE(n.value, 0.0);
    someGoal = someGoal || n.goal;
  }
  EXPECT_TRUE(someGoal) << "the plan's goal came from a cached node";
  r.algorithm = PlanAlgorithm::kDecoupled;
  EXPECT_TRUE(planGrasp(world(), r).explored.empty()) << "the decoupled sampler has no cache";
}

TEST(GraspMotionPlanner, SameSeedGivesTheSamePath) {
  // Without the physics check: a check cut short by the time limit makes
  // the search depend on the machine's speed (docs/planning.md).
  PlanRequest r = request("bin", "blob", 5);
  r.parameters["physics_check"] = "0";
  const PlanResult a = planGrasp(world(), r);
  const PlanResult b = planGrasp(world(), r);
  ASSERT_TRUE(a.success && b.success);
  ASSERT_EQ(a.path.size(), b.path.size());
  for (std::size_t i = 0; i < a.path.size(); ++i) EXPECT_EQ(a.path[i], b.path[i]);
  EXPECT_EQ(a.grasp.node, b.grasp.node);
  EXPECT_EQ(a.stats.iterations, b.stats.iterations);
  EXPECT_EQ(a.stats.collision_checks, b.stats.collision_checks);
}

TEST(GraspMotionPlanner, ThePaperPresetTurnsEveryAdditionOffWhateverTheRobotConfigSays) {
  // Every setting is a declared parameter, at a value inside its range.
  std::map<std::string, std::string> declared;
  for (const PlannerParameterInfo& p : plannerParameters(world()))
    declared[p.name] = p.default_value;
  for (const auto& [name, value] : paperSettings()) {
    EXPECT_EQ(declared.count(name), 1u) << name;
    PlanRequest r = request("table", "mug", 1);
    r.parameters[name] = value;
    r.time_limit = 0.0;
    EXPECT_NO_THROW(planGrasp(world(), r)) << name << "=" << value;
  }
  // The additions and physics_check default to 1: the preset turns them
  // off, as naming every setting in the request does.
  EXPECT_EQ(declared.at("physics_check"), "1");
  EXPECT_EQ(declared.at("other_postures"), "1");
  PlanRequest paper = request("table", "mug", 3);
  paper.preset = PlannerPreset::kPaper;
  PlanRequest named = request("table", "mug", 3);
  named.parameters = paperSettings();
  const PlanResult a = planGrasp(world(), paper);
  const PlanResult b = planGrasp(world(), named);
  ASSERT_TRUE(a.success && b.success) << a.message << " / " << b.message;
  ASSERT_EQ(a.path.size(), b.path.size());
  for (std::size_t i = 0; i < a.path.size(); ++i) EXPECT_EQ(a.path[i], b.path[i]);
  EXPECT_EQ(a.stats.collision_checks, b.stats.collision_checks);
  EXPECT_FALSE(a.validation.has_value()) << "no physics check ran";
  // The request's parameters still apply over the preset.
  paper.parameters["physics_check"] = "1";
  const PlanResult checked = planGrasp(world(), paper);
  ASSERT_TRUE(checked.success) << checked.message;
  ASSERT_TRUE(checked.validation.has_value() && checked.validation->physics.has_value());
  EXPECT_TRUE(checked.validation->physics->held);
}

TEST(GraspMotionPlanner, RacingCopiesPlanAndTheWinnersSeedReplaysItsPlan) {
  PlanRequest r = request("table", "mug", 4);
  r.parameters["threads"] = "3";
  r.parameters["physics_check"] = "0";  // the race and its replay, not whether plans hold
  const PlanResult raced = planGrasp(world(), r);
  expectValidPlan(r, raced);
  std::vector<std::uint64_t> seeds;
  for (int copy = 0; copy < 3; ++copy) seeds.push_back(racingSeed(r.seed, copy));
  EXPECT_NE(std::find(seeds.begin(), seeds.end(), raced.seed), seeds.end()) << raced.seed;
  // One thread with the winner's seed plans the same path again.
  r.parameters["threads"] = "1";
  r.seed = raced.seed;
  const PlanResult replayed = planGrasp(world(), r);
  ASSERT_TRUE(replayed.success);
  EXPECT_EQ(replayed.seed, raced.seed);
  ASSERT_EQ(replayed.path.size(), raced.path.size());
  for (std::size_t i = 0; i < raced.path.size(); ++i) EXPECT_EQ(replayed.path[i], raced.path[i]);
  EXPECT_EQ(replayed.grasp.node, raced.grasp.node);
}

TEST(GraspMotionPlanner, RacingSeedsKeepTheFirstAndDifferForTheOthers) {
  EXPECT_EQ(racingSeed(7, 0), 7u);
  std::vector<std::uint64_t> seeds;
  for (const std::uint64_t seed : {0u, 1u, 2u})
    for (int copy = 0; copy < 8; ++copy) seeds.push_back(racingSeed(seed, copy));
  std::sort(seeds.begin(), seeds.end());
  EXPECT_EQ(std::adjacent_find(seeds.begin(), seeds.end()), seeds.end());
  EXPECT_EQ(racingSeed(1, 3), racingSeed(1, 3));
}

TEST(GraspMotionPlanner, RacingCopiesStopWhenCancelledOrOutOfTime) {
  PlanRequest r = request("table", "mug", 1);
  r.parameters["threads"] = "2";
  std::atomic<bool> cancel{true};
  const PlanResult cancelled = planGrasp(world(), r, &cancel);
  EXPECT_FALSE(cancelled.success);
  EXPECT_EQ(cancelled.failure, PlanFailure::kCancelled);
  // No copy can succeed without goal sampling: the result is copy 0's
  // failure, at the time limit.
  r.parameters["p_max"] = "0";
  r.parameters["p_min"] = "0";
  r.time_limit = 0.2;
  const PlanResult none = planGrasp(world(), r);
  EXPECT_FALSE(none.success);
  EXPECT_EQ(none.failure, PlanFailure::kNoValidGoal);
  EXPECT_EQ(none.seed, r.seed);
  EXPECT_GE(none.stats.planning_time, searchTimeLimit(0.2));
}

TEST(GraspMotionPlanner, TheSphereTierChangesNoPlan) {
  for (const char* scene : {"bin", "shelf"}) {
    PlanRequest r = request(scene, scene == std::string("bin") ? "blob" : "mug", 2);
    r.parameters["physics_check"] = "0";  // collision answers, not whether plans hold
    r.parameters["sphere_tier"] = "0";
    const PlanResult fclOnly = planGrasp(world(), r);
    r.parameters["sphere_tier"] = "1";
    const PlanResult twoTiers = planGrasp(world(), r);
    ASSERT_TRUE(fclOnly.success && twoTiers.success) << scene;
    ASSERT_EQ(fclOnly.path.size(), twoTiers.path.size()) << scene;
    for (std::size_t i = 0; i < fclOnly.path.size(); ++i)
      EXPECT_EQ(fclOnly.path[i], twoTiers.path[i]);
    EXPECT_EQ(fclOnly.stats.iterations, twoTiers.stats.iterations);
    EXPECT_EQ(fclOnly.stats.collision_checks, twoTiers.stats.collision_checks);
  }
}

TEST(GraspMotionPlanner, EveryGraspPlanLiftsTheObjectClearOfItsSupport) {
  PlanRequest r = request("table", "box", 1);
  r.parameters["physics_check"] = "0";
  const PlanResult lifted = planGrasp(world(), r);
  expectValidPlan(r, lifted);  // the lift's checks too
  ASSERT_TRUE(lifted.lift.has_value());
  // The trajectory carries the lift after the closing.
  ASSERT_FALSE(lifted.trajectory.points.empty());
  EXPECT_GT(lifted.trajectory.lift_start, lifted.trajectory.closing_start);
  EXPECT_LT(lifted.trajectory.lift_start, lifted.trajectory.duration);
  EXPECT_TRUE(lifted.trajectory.points.back().positions.isApprox(lifted.lift->path.back(), 1e-9));
  // Without a lift the plan ends with the hand closed.
  r.lift.reset();
  const PlanResult closed = planGrasp(world(), r);
  ASSERT_TRUE(closed.success) << closed.message;
  EXPECT_FALSE(closed.lift.has_value());
  EXPECT_DOUBLE_EQ(closed.trajectory.lift_start, closed.trajectory.duration);
  EXPECT_TRUE(closed.trajectory.points.back().positions.isApprox(closed.path.back(), 1e-9));
  r.lift = LiftOptions{0.0};
  test::expectErrorMentioning<InvalidArgument>([&] { planGrasp(world(), r); }, {"lift.height"});
  r.lift = LiftOptions{0.1, 1.5};
  test::expectErrorMentioning<InvalidArgument>([&] { planGrasp(world(), r); }, {"lift.held_speed"});
}

/// Adds to `r` a square board `size` wide, centred over the target object,
/// its underside `headroom` above the object's top.
void addBoardAbove(PlanRequest& r, double headroom, double size) {
  const robot::Scene scene = test::plannedScene(world(), r);
  const db::ObjectDatabase& object = *world().object(scene.target_object);
  double top = -1e9;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (Eigen::Index v = 0; v < object.geometry.mesh_vertices.rows(); ++v) {
    const Eigen::Vector3d p = scene.target_pose * object.geometry.mesh_vertices.row(v).transpose();
    top = std::max(top, p.z());
    centre += p;
  }
  centre /= static_cast<double>(object.geometry.mesh_vertices.rows());
  robot::Obstacle board;
  board.name = "board";
  board.type = robot::Obstacle::Type::kBox;
  board.size = Eigen::Vector3d(size, size, 0.01);
  board.pose.translation() = Eigen::Vector3d(centre.x(), centre.y(), top + headroom + 0.005);
  r.scene.obstacles.push_back(board);
}

TEST(GraspMotionPlanner, AnObjectUnderABoardIsSlidOutOrLiftedByAPlannedMotion) {
  // A board 30 cm wide 4 cm above the box: no straight line lifts it the
  // 10 cm; sliding it out from under the board, or a planned motion, does.
  // Of these two seeds' grasps one is slid out and one needs the planned
  // lift, so that both fallbacks are exercised.
  std::vector<std::string> directions;
  for (std::uint64_t seed = 1; seed <= 2; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    // The table scene's table, its clutter gone: a scene of this test's own.
    PlanRequest r = request("table", "box", seed);
    r.parameters["physics_check"] = "0";
    auto& obstacles = r.scene.obstacles;
    obstacles.erase(std::remove_if(obstacles.begin(), obstacles.end(),
                                   [](const robot::Obstacle& o) { return o.name != "table"; }),
                    obstacles.end());
    addBoardAbove(r, 0.04, 0.3);
    const PlanResult result = planGrasp(world(), r);
    expectValidPlan(r, result);  // the lift's checks, whatever its kind
    ASSERT_TRUE(result.lift.has_value());
    directions.push_back(result.lift->direction);
    EXPECT_FALSE(result.trajectory.points.empty());
  }
  const auto slid = [](const std::string& d) { return d.rfind("out_", 0) == 0; };
  EXPECT_EQ(std::count(directions.begin(), directions.end(), "planned"), 1) << directions[0];
  EXPECT_EQ(std::count_if(directions.begin(), directions.end(), slid), 1) << directions[1];
}

TEST(GraspMotionPlanner, ABoardAboveTheObjectInClutterBlocksEveryLift) {
  // The bundled table scene with a board 3.5 cm above the box: no straight
  // line lifts it, the slides out from under the board meet the jar or the
  // KR5's joint limits, and no planned motion is found within its second:
  // goals are found and reached, and each is dropped for its lift; without
  // a lift the box is grasped.
  PlanRequest r = request("table", "box", 1);
  r.parameters["physics_check"] = "0";
  addBoardAbove(r, 0.03, 0.3);
  r.time_limit = 5.0;
  const PlanResult blocked = planGrasp(world(), r);
  EXPECT_FALSE(blocked.success);
  EXPECT_EQ(blocked.failure, PlanFailure::kTimeLimit);
  EXPECT_GT(blocked.stats.rejected.lift_blocked, 0u);
  // (The last one's lift may have been cut short by the time limit.)
  EXPECT_LE(blocked.stats.dropped_goals, blocked.stats.rejected.lift_blocked + 1);
  EXPECT_NE(
      blocked.message.find(std::to_string(blocked.stats.rejected.lift_blocked) + " no free lift"),
      std::string::npos)
      << blocked.message;
  r.lift.reset();
  expectValidPlan(r, planGrasp(world(), r));
}

TEST(GraspMotionPlanner, TheRobotHoldingTheObjectCarriesItWithItsHandAsItClosed) {
  PlanRequest r = request("table", "box", 1);
  r.parameters["physics_check"] = "0";
  const PlanResult picked = planGrasp(world(), r);
  ASSERT_TRUE(picked.success && picked.lift) << picked.message;
  const robot::Scene scene = test::plannedScene(world(), r);
  const db::ObjectDatabase& box = *world().object(scene.target_object);
  const Eigen::VectorXd& grasp = picked.path.back();
  const Hold hold = holdObject(world().collisionModel(), scene.robot_base, box.geometry, box.name,
                               scene.target_pose, grasp);
  const std::shared_ptr<const PlanningWorld> carrying = carryWorld(world(), hold, grasp);
  EXPECT_FALSE(carrying->canGrasp());
  robot::Scene obstacles = scene;
  obstacles.target_object.clear();
  robot::CollisionChecker held(*hold.model, obstacles, nullptr);
  // From the lift's end to the first joint turned, a goal free with the
  // object in the hand.
  PlanRequest carry;
  carry.scene = obstacles;
  carry.start = picked.lift->path.back();
  Eigen::VectorXd goal = *carry.start;
  for (const double turn : {0.8, -0.8, 0.5, -0.5, 1.2, -1.2}) {
    goal = *carry.start;
    goal(0) += turn;
    if (world().robot().withinLimits(goal) && !held.inCollision(goal)) break;
  }
  ASSERT_FALSE(held.inCollision(goal));
  carry.goals = {JointGoal{goal}};
  carry.time_limit = 10.0;
  const PlanResult moved = planGrasp(*carrying, carry);
  ASSERT_TRUE(moved.success) << moved.message;
  ASSERT_GE(moved.path.size(), 2u);
  EXPECT_TRUE(moved.path.back().isApprox(goal, 1e-9));
  const int hand = world().robot().numHandDofs();
  const int link = hold.model->robot.heldLink();
  for (std::size_t i = 0; i < moved.path.size(); ++i) {
    // The hand as it closed, the object where the palm holds it.
    EXPECT_TRUE(moved.path[i].tail(hand).isApprox(grasp.tail(hand), 1e-12));
    const robot::LinkPoses poses = robot::forwardKinematics(hold.model->robot, moved.path[i]);
    const Eigen::Isometry3d palm = poses[static_cast<std::size_t>(world().robot().palmLink())];
    EXPECT_TRUE(poses[static_cast<std::size_t>(link)].isApprox(palm * hold.object_in_palm, 1e-9));
    if (i > 0) {
      EXPECT_TRUE(held.isMotionValid(moved.path[i - 1], moved.path[i], test::kFinalResolution))
          << "segment " << i;
    }
  }
  // A grasp is no plan of the carrying world.
  test::expectErrorMentioning<InvalidArgument>([&] { planGrasp(*carrying, r); },
                                               {"goals", "holds an object"});
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
  EXPECT_EQ(result.failure, PlanFailure::kNoValidGoal);  // none was even looked for
  EXPECT_EQ(result.stats.goal_sampling_calls, 0u);
  EXPECT_EQ(result.message,
            "no valid goal within the time limit; of the 0 leaf grasps tried: none tried");
  EXPECT_GE(elapsed, searchTimeLimit(0.3));
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

TEST(GraspMotionPlanner, AnObjectInsideAnObstacleIsReportedAtOnce) {
  PlanRequest r = request("table", "mug", 1);
  r.object_pose = r.scene.target_pose;
  r.object_pose->translation().x() = 0.72;  // into the tall box behind the target
  const PlanResult result = planGrasp(world(), r);
  EXPECT_FALSE(result.success);
  EXPECT_EQ(result.failure, PlanFailure::kObjectInCollision);
  EXPECT_NE(result.message.find("tall_box"), std::string::npos) << result.message;
  EXPECT_EQ(result.stats.goal_sampling_calls, 0u);  // nothing was searched
}

TEST(GraspMotionPlanner, AnObjectThatRestsOnASupportIsPutOnItsTop) {
  PlanRequest r = request("table", "bottle", 1);
  r.time_limit = 0.0;
  r.scene.target_pose.translation().z() = 0.3;  // floating above the table ...
  r.scene.target_rest_on = "table";             // ... until it is put on it
  const PlanResult result = planGrasp(world(), r);
  const double tableTop = robot::topOf(*r.scene.obstacle("table")) + robot::kRestingClearance;
  const double lowest = world().object("bottle")->geometry.mesh_vertices.col(2).minCoeff();
  EXPECT_NEAR(result.object_pose.translation().z(), tableTop - lowest, 1e-12);
  EXPECT_NE(result.failure, PlanFailure::kObjectInCollision);
  // Lying on its side, it rests on its curved surface.
  r.scene.target_pose.linear() =
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const PlanResult lying = planGrasp(world(), r);
  const double radius = -world().object("bottle")->geometry.mesh_vertices.col(1).minCoeff();
  EXPECT_NEAR(lying.object_pose.translation().z(), tableTop + radius, 1e-9);
  // An explicit object pose is used as it is.
  r.object_pose = Eigen::Isometry3d(Eigen::Translation3d(0.55, 0, 0.2));
  EXPECT_NEAR(planGrasp(world(), r).object_pose.translation().z(), 0.2, 1e-12);
}

/// The box standing in a tight slot on the table: walls 1 mm from its four
/// sides leave a fingertip only its top face.
PlanRequest boxInASlot(double timeLimit) {
  PlanRequest r = request("table", "box", 1);
  r.time_limit = timeLimit;
  robot::Scene& s = r.scene;
  s.obstacles.erase(std::remove_if(s.obstacles.begin(), s.obstacles.end(),
                                   [](const robot::Obstacle& o) { return o.name != "table"; }),
                    s.obstacles.end());
  const Eigen::Vector3d at = s.target_pose.translation();
  const auto wall = [&](const char* name, double dx, double dy, double sx, double sy) {
    robot::Obstacle o;
    o.name = name;
    o.size << sx, sy, 0.25;
    o.pose.translation() = at + Eigen::Vector3d(dx, dy, 0.125);
    s.obstacles.push_back(o);
  };
  wall("left", 0, -0.031 - 0.01, 0.3, 0.02);  // the box is 8 x 6 cm
  wall("right", 0, 0.031 + 0.01, 0.3, 0.02);
  wall("front", 0.041 + 0.01, 0, 0.02, 0.3);
  wall("back", -0.041 - 0.01, 0, 0.02, 0.3);
  s.target_rest_on = "table";
  return r;
}

TEST(GraspMotionPlanner, FailsAtOnceWhenNoStableGraspIsClearOfTheSupport) {
  const PlanResult result = planGrasp(world(), boxInASlot(10.0));
  EXPECT_EQ(result.failure, PlanFailure::kNoStableGraspClearOfSupport) << result.message;
  EXPECT_LT(result.stats.planning_time, 1.0);
  EXPECT_EQ(result.stats.goal_sampling_calls, 0u);
  EXPECT_NE(result.message.find("pad radius 14 mm"), std::string::npos) << result.message;
  // Without the mask the search has every contact and runs to its limit.
  PlanRequest unmasked = boxInASlot(0.5);
  unmasked.parameters["mask_contacts"] = "0";
  const PlanResult searched = planGrasp(world(), unmasked);
  EXPECT_FALSE(searched.success);
  EXPECT_NE(searched.failure, PlanFailure::kNoStableGraspClearOfSupport);
  EXPECT_GE(searched.stats.planning_time, searchTimeLimit(0.5));
}

TEST(Holdability, TheKr5HoldsTheMugOnTheTableButNothingInTheSlot) {
  const PlanRequest mug = request("table", "mug", 1);
  const Holdability held = holdability(world(), mug);
  ASSERT_TRUE(held.holdable) << held.reason;
  EXPECT_TRUE(held.reason.empty());
  EXPECT_GT(held.epsilon, 0.0);
  EXPECT_GE(held.hand_clear, 1);
  EXPECT_GE(held.reached, held.hand_clear);
  EXPECT_GE(held.stable, held.reached);
  EXPECT_GE(held.leaves, held.stable);
  EXPECT_GE(held.climbs, 1);
  const Holdability again = holdability(world(), mug);  // deterministic
  EXPECT_EQ(again.leaves, held.leaves);
  EXPECT_EQ(again.epsilon, held.epsilon);

  // The slot leaves no stable grasp: decided before any climb, as a plan is.
  const Holdability slot = holdability(world(), boxInASlot(1.0));
  EXPECT_FALSE(slot.holdable);
  EXPECT_EQ(slot.climbs, 0);
  EXPECT_NE(slot.reason.find("no stable grasp is possible"), std::string::npos) << slot.reason;

  // 3 m away: beyond the fingertips' reach ball, decided before any climb.
  const Holdability far =
      holdability(world(), test::outOfReachRequest(PlanAlgorithm::kCoupled), 20);
  EXPECT_FALSE(far.holdable);
  EXPECT_EQ(far.climbs, 0);
  EXPECT_NE(far.reason.find("out of reach"), std::string::npos) << far.reason;
  // 1.3 m away the hand alone takes the mug, the arm does not reach it.
  const Holdability near =
      holdability(world(), test::justOutOfReachRequest(PlanAlgorithm::kCoupled), 20);
  EXPECT_FALSE(near.holdable);
  EXPECT_GT(near.hand_clear, 0);
  EXPECT_EQ(near.climbs, 20);
  EXPECT_NE(near.reason.find("none with a collision-free arm configuration"), std::string::npos)
      << near.reason;

  PlanRequest unknown = mug;
  unknown.object = "nothing";
  EXPECT_EQ(holdability(world(), unknown).reason, "unknown object 'nothing'");
  test::expectErrorMentioning<InvalidArgument>([&] { holdability(world(), mug, 0); },
                                               {"climbs", "at least 1"});
}

TEST(Holdability, AParallelGripperHoldsTheBoxButNotTheWideCarton) {
  static const PlanningWorld panda = [] {
    const robot::RobotModel model =
        robot::RobotModel::load(test::sourcePath("robots/panda_gripper/panda_gripper.json"));
    std::map<std::string, db::ObjectDatabase> objects;
    for (const char* name : {"box", "carton"})  // only these two: the others cost seconds
      objects.emplace(name, preprocess::buildObjectDatabaseFromFile(
                                test::bundledMeshDir() / (std::string(name) + ".stl"),
                                test::fixtureParameters())
                                .database);
    return PlanningWorld(model, grasp::buildHandMap(model, grasp::handMapOptions(model)),
                         std::move(objects));
  }();
  const Holdability box = holdability(panda, request("table", "box", 1));
  EXPECT_TRUE(box.holdable) << box.reason;
  // The carton is wider than the 8 cm jaws open everywhere a finger fits.
  const Holdability carton = holdability(panda, request("table", "carton", 1), 20);
  EXPECT_FALSE(carton.holdable);
  EXPECT_EQ(carton.climbs, 20);
  EXPECT_EQ(carton.reached, 0);
  EXPECT_GT(carton.leaves, 20);
  EXPECT_NE(carton.reason.find(" leaves of 20 climbs: 0 stable"), std::string::npos)
      << carton.reason;
}

TEST(GraspMotionPlanner, ByDefaultEveryPlanIsAGraspThatHeldInPhysics) {
  PlanRequest r = request("shelf", "bottle", 1);
  r.validate = true;
  const PlanResult result = planGrasp(world(), r);
  ASSERT_TRUE(result.success) << result.message;
  ASSERT_TRUE(result.validation && result.validation->physics);
  const physics::GraspVerdict& verdict = *result.validation->physics;
  EXPECT_TRUE(verdict.held) << verdict.held_fraction;
  EXPECT_GE(verdict.held_fraction, physics::SimulationOptions{}.min_held_fraction);
  EXPECT_TRUE(result.validation->holds());
  // Off, the search ends at the first goal it reaches and drops none.
  r.parameters["physics_check"] = "0";
  r.validate = false;
  const PlanResult unchecked = planGrasp(world(), r);
  ASSERT_TRUE(unchecked.success) << unchecked.message;
  EXPECT_EQ(unchecked.stats.dropped_goals, 0u);
  EXPECT_FALSE(unchecked.validation);
}

TEST(GraspMotionPlanner, MaskedGraspsNeverUseContactsAFingertipCannotTouch) {
  // The box on the bare table: its lowest 13 mm are out of a fingertip's
  // reach; every planned contact lies higher.
  PlanRequest r = request("table", "box", 1);
  r.scene.obstacles.erase(r.scene.obstacles.begin() + 1, r.scene.obstacles.end());
  r.scene.target_rest_on = "table";
  r.parameters["physics_check"] = "0";  // which contacts, not whether they hold
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    r.seed = seed;
    const PlanResult result = planGrasp(world(), r);
    ASSERT_TRUE(result.success) << result.message;
    const double bottom = result.object_pose.translation().z();
    for (Eigen::Index f = 0; f < result.grasp.contacts_world.cols(); ++f) {
      const Eigen::Vector3d c = result.grasp.contacts_world.col(f);
      const Eigen::Vector3d outward = -result.grasp.inward_normals_world.col(f);
      // The pad's sphere (radius 14 mm, less the 1 mm clearance) clears the table top.
      EXPECT_GT((c + 0.014 * outward).z() - 0.013, bottom - 0.001 - 1e-9) << "seed " << seed;
    }
  }
}

TEST(GraspMotionPlanner, GoalsWithoutAPathEndAtTheTimeLimit) {
  // Only goal sampling, no tree growth (p_g = 1): goals are found, no path.
  PlanRequest r = request("table", "mug", 1);
  r.time_limit = 1.0 * test::sanitizerSlowdown();
  r.parameters = {{"p_max", "1"}, {"p_min", "1"}};
  const PlanResult result = planGrasp(world(), r);
  EXPECT_EQ(result.failure, PlanFailure::kTimeLimit) << result.message;
  EXPECT_GT(result.stats.valid_goal_samples, 0u);
  EXPECT_NE(result.message.find("no path"), std::string::npos) << result.message;
}

TEST(GraspMotionPlanner, OtherPosturesPlansAreValidAndCountEveryPosture) {
  // The mug on the bare table, every goal hand posture of a grasp tried.
  PlanRequest r = request("table", "mug", 2);
  r.parameters["other_postures"] = "1";
  r.parameters["physics_check"] = "0";  // which postures are goals, not whether they hold
  const PlanResult result = planGrasp(world(), r);
  expectValidPlan(r, result);
  const GraspRejections& x = result.stats.rejected;
  EXPECT_EQ(x.total(), x.unstable + x.no_arm_ik + x.out_of_hand_reach + x.colliding +
                           x.no_pad_contact + x.weak_at_contacts + x.closing_blocked);
}

TEST(GraspMotionPlanner, UnknownObjectIsReported) {
  const PlanResult result = planGrasp(world(), request("table", "teapot", 1));
  EXPECT_FALSE(result.success);
  EXPECT_EQ(result.failure, PlanFailure::kUnknownObject);
  EXPECT_NE(result.message.find("teapot"), std::string::npos);
}

TEST(GraspMotionPlanner, UnreachableObjectIsReported) {
  // 3 m away the object is beyond the fingertips' reach ball: refused
  // before any grasp is sampled, with the distances.
  const PlanResult far = planGrasp(world(), test::outOfReachRequest(PlanAlgorithm::kCoupled));
  EXPECT_FALSE(far.success);
  EXPECT_EQ(far.failure, PlanFailure::kObjectUnreachable) << far.message;
  EXPECT_EQ(far.stats.goal_sampling_calls, 0u);
  EXPECT_NE(far.message.find("out of reach: its surface is 2.97"), std::string::npos)
      << far.message;
  EXPECT_NE(far.message.find("no fingertip reaches farther than 1.30"), std::string::npos)
      << far.message;
  // Inside the ball, beyond the arm: found out by searching.
  const PlanResult near = planGrasp(world(), test::justOutOfReachRequest(PlanAlgorithm::kCoupled));
  EXPECT_FALSE(near.success);
  EXPECT_EQ(near.failure, PlanFailure::kObjectUnreachable) << near.message;
  EXPECT_GT(near.stats.goal_sampling_calls, 0u);
  EXPECT_NE(near.message.find("grasps tried has an arm IK solution"), std::string::npos)
      << near.message;
}

/// What planGrasp rejects `r` with ("" when it accepts it).
std::string rejection(const PlanRequest& r, std::string* field = nullptr) {
  try {
    planGrasp(world(), r);
  } catch (const InvalidArgument& e) {
    if (field != nullptr) *field = e.field();
    return e.what();
  }
  return "";
}

TEST(GraspMotionPlanner, MalformedRequestsThrowNamingTheField) {
  PlanRequest r = request("table", "mug", 1);
  r.time_limit = 0.0;  // only the checks matter here
  std::string field;
  r.start = Eigen::VectorXd::Zero(5);
  EXPECT_EQ(rejection(r, &field), "start: 13 values expected, got 5");
  EXPECT_EQ(field, "start");
  r.start = world().robot().home();
  (*r.start)(0) = 10.0;
  EXPECT_NE(rejection(r, &field).find("start: value 10.000000 of 'a1' is outside"),
            std::string::npos);
  r.start.reset();
  r.time_limit = -1.0;
  EXPECT_EQ(rejection(r, &field), "time_limit: must be a finite number >= 0");
  EXPECT_EQ(field, "time_limit");
  r.time_limit = 0.0;
  r.parameters = {{"no_such", "1"}};
  EXPECT_EQ(rejection(r, &field), "parameters.no_such: unknown planner parameter");
  EXPECT_EQ(field, "parameters.no_such");
  r.parameters = {{"time_limit", "5"}};  // a request field, not a parameter
  EXPECT_EQ(rejection(r), "parameters.time_limit: unknown planner parameter");
  r.parameters = {{"p_max", "2"}};
  EXPECT_EQ(rejection(r, &field), "parameters.p_max: must be in [0, 1], got 2");
  EXPECT_EQ(field, "parameters.p_max");
  r.parameters = {{"threads", "0"}};
  EXPECT_EQ(rejection(r, &field), "parameters.threads: must be in [1, 32], got 0");
  EXPECT_EQ(field, "parameters.threads");
  r.parameters = {{"threads", "2"}, {"p_max", "2"}};  // every racing copy checks the request
  EXPECT_EQ(rejection(r, &field), "parameters.p_max: must be in [0, 1], got 2");
  r.parameters = {{"kappa", "many"}};
  EXPECT_EQ(rejection(r), "parameters.kappa: must be an integer, got 'many'");
  r.parameters = {{"kappa", "2.5"}};
  EXPECT_EQ(rejection(r), "parameters.kappa: must be an integer, got '2.5'");
  r.parameters = {{"i_min", "50"}, {"i_max", "30"}};
  EXPECT_EQ(rejection(r, &field),
            "parameters.i_min: must be <= i_max, got i_min = 50 > i_max = 30");
  EXPECT_EQ(field, "parameters.i_min");
  r.parameters.clear();
  r.algorithm = PlanAlgorithm::kDecoupled;
  r.iterations = 0;
  EXPECT_EQ(rejection(r, &field), "iterations: must be in [1, 100000], got 0");
  EXPECT_EQ(field, "iterations");
}

TEST(GraspMotionPlanner, EveryParameterEnforcesTheRangeItDeclares) {
  for (const PlannerParameterInfo& p : plannerParameters(world())) {
    SCOPED_TRACE(p.name + " " + p.range);
    const std::string low = p.range.substr(0, p.range.find(':'));
    const std::string high = p.range.substr(p.range.rfind(':') + 1);
    const ParameterRange range = ParameterRange::fromSuggestion(p.range);
    ASSERT_LT(range.low, range.high);
    PlanRequest r = request("table", "mug", 1);
    r.time_limit = 0.0;  // only the parameters matter here
    // i_min <= i_max holds at both ends of either range.
    if (p.name == "i_min") r.parameters["i_max"] = "100000";
    if (p.name == "i_max") r.parameters["i_min"] = "0";
    for (const std::string& inside : {low, high}) {
      r.parameters[p.name] = inside;
      EXPECT_EQ(rejection(r), "") << inside;
    }
    // One below and one above (whole numbers when the bounds are).
    std::ostringstream below, above;
    below.precision(17);
    above.precision(17);
    below << range.low - 1.0;
    above << range.high + 1.0;
    for (const std::string& outside : {below.str(), above.str()}) {
      r.parameters[p.name] = outside;
      EXPECT_EQ(rejection(r), "parameters." + p.name + ": must be in [" + low + ", " + high +
                                  "], got " + outside);
    }
  }
}

TEST(GraspMotionPlanner, DeclaresThePaperParametersWithTheirDefaults) {
  std::map<std::string, double> expected = {{"p_max", 0.9},
                                            {"p_goal_tree", 0.7},
                                            {"p_min", 0.01},
                                            {"d_m", 0.4},
                                            {"w_f", 0.5},
                                            {"n_a", 20},
                                            {"w_c", 4.0},
                                            {"alpha", 1e-6},
                                            {"kappa", 4},
                                            {"p_w", 1.2},
                                            {"weight_arm", 1.0},
                                            {"weight_hand", 0.25},
                                            {"i_min", 20},
                                            {"i_max", 100},
                                            {"friction", 0.5},
                                            {"cone_edges", 8},
                                            {"step_size", 0.1},
                                            {"iterations", 20},
                                            {"smoothing_steps", 200},
                                            {"final_resolution", 0.0025},
                                            {"collision_resolution", 0.02},
                                            // The KR5's planner_defaults (the planner's
                                            // own is 0.005, the Panda's default).
                                            {"max_fingertip_error", 0.008},
                                            // The additions kept on held-out evidence
                                            // (docs/planning.md), on for every hand.
                                            {"unstable_by_reach", 1},
                                            {"fit_check", 1},
                                            {"fit_clearance", 0.0},
                                            {"palm_turns", 8},
                                            {"other_postures", 1},
                                            {"mask_contacts", 1},
                                            {"p_local", 1.0},
                                            {"local_radius", 0.8},
                                            // A goal is a grasp that holds
                                            // (docs/planning.md#what-a-goal-is).
                                            {"min_epsilon", 0.002},
                                            {"max_penetration", 0.001},
                                            {"physics_check", 1},
                                            // Paths sampled, not proven
                                            // (docs/planning.md#certified-paths).
                                            {"certify_path", 0},
                                            {"clearance", 0.0}};
  for (const PlannerParameterInfo& p : plannerParameters(world())) {
    const auto it = expected.find(p.name);
    if (it == expected.end()) continue;
    EXPECT_NEAR(std::stod(p.default_value), it->second, 1e-12 + 1e-9 * it->second) << p.name;
    expected.erase(it);
  }
  for (const auto& [name, value] : expected) ADD_FAILURE() << "not declared: " << name;
  EXPECT_EQ(plannerParameters(world()).size(), 37u) << "a parameter was added or removed";
}

/// The bundled KR5 + SDH with these `planner_defaults` instead of its own.
robot::RobotModel kr5WithDefaults(const std::string& defaults) {
  std::string config = test::readBytes(test::sourcePath("robots/kr5_sdh/kr5_sdh.json"));
  const std::string key = "\"planner_defaults\": ";
  const std::size_t at = config.find(key);
  const std::size_t end = config.find('}', at);
  if (at == std::string::npos || end == std::string::npos)
    throw std::runtime_error("kr5_sdh.json has no planner_defaults object");
  config.replace(at, end + 1 - at, key + defaults);
  return robot::RobotModel::fromStrings(
      test::readBytes(test::sourcePath("robots/kr5_sdh/kr5_sdh.urdf")), config, "kr5 defaults");
}

TEST(GraspMotionPlanner, ARobotConfigsPlannerDefaultsReplaceThePlannersAndAreChecked) {
  const robot::RobotModel model = kr5WithDefaults(R"({"other_postures": 0, "p_max": 0.75})");
  const PlanningWorld changed(model, grasp::buildHandMap(model),
                              std::map<std::string, db::ObjectDatabase>{});
  std::map<std::string, std::string> defaults;
  for (const PlannerParameterInfo& p : plannerParameters(changed))
    defaults[p.name] = p.default_value;
  EXPECT_EQ(defaults.at("other_postures"), "0");
  EXPECT_EQ(std::stod(defaults.at("p_max")), 0.75);
  EXPECT_EQ(defaults.at("fit_check"), "1") << "the others stay the planner's";
  EXPECT_EQ(std::stod(defaults.at("max_fingertip_error")), 0.005);
  for (const auto& [bad, words] : std::vector<std::pair<std::string, std::string>>{
           {R"({"warp": 1})", "robot config 'kr5_sdh': planner_defaults.warp:"},
           {R"({"p_max": 2})",
            "robot config 'kr5_sdh': planner_defaults.p_max: must be in [0, 1]"}}) {
    const robot::RobotModel broken = kr5WithDefaults(bad);
    const PlanningWorld world(broken, grasp::buildHandMap(broken),
                              std::map<std::string, db::ObjectDatabase>{});
    test::expectErrorMentioning<robot::ModelError>([&] { plannerParameters(world); }, {words});
  }
}

}  // namespace
}  // namespace hfts::planner
