// Motion-only goals (planner/motion_goal.h): joint goals, pose goals and
// sets of goals through the multi-tree planner, with no grasp.
#include "planner/motion_goal.h"

#include <gtest/gtest.h>

#include <random>

#include "core/invalid_argument.h"
#include "planner/grasp_motion_planner.h"
#include "robot/kinematics.h"
#include "robot/moveit_problem.h"
#include "robot/segment_certificate.h"

#include "motion_goal_sampler.h"
#include "plan_checks.h"

namespace hfts::planner {
namespace {

const PlanningWorld& world() {
  return test::bundledWorld();
}
const robot::RobotModel& robot() {
  return world().robot();
}

/// The shelf scene with its bottle, planned as a motion.
PlanRequest shelfRequest(std::uint64_t seed) {
  PlanRequest r = test::bundledSceneRequest("shelf", "bottle", seed, PlanAlgorithm::kCoupled);
  r.time_limit = 60.0 * test::sanitizerSlowdown();
  return r;
}

/// A collision-free configuration of the request's scene (the object where
/// it stands) drawn uniformly within the joint limits, the hand as in
/// `hand`, whose palm is at least `away` m from the start's.
Eigen::VectorXd freeConfiguration(const PlanRequest& r, const Eigen::VectorXd& hand,
                                  std::uint64_t seed, double away = 0.3) {
  const robot::Scene scene = test::plannedScene(world(), r);
  robot::CollisionChecker checker(world().collisionModel(), scene,
                                  &world().object(scene.target_object)->geometry);
  const Eigen::VectorXd start = r.scene.startFor(robot().name()).value_or(robot().home());
  const auto palmOf = [](const Eigen::VectorXd& q) -> Eigen::Vector3d {
    return robot::forwardKinematics(robot(), q)[static_cast<std::size_t>(robot().palmLink())]
        .translation();
  };
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int attempt = 0; attempt < 100000; ++attempt) {
    Eigen::VectorXd q = start;
    for (int d = 0; d < robot().numArmDofs(); ++d)
      q(d) = robot().lowerLimits()(d) +
             unit(rng) * (robot().upperLimits()(d) - robot().lowerLimits()(d));
    q.tail(hand.size()) = hand;
    if ((palmOf(q) - palmOf(start)).norm() >= away && !checker.inCollision(q)) return q;
  }
  ADD_FAILURE() << "no free configuration found";
  return start;
}

/// Every segment of the path free at 1/400 of its length, by FCL (the
/// object where the request puts it, as an obstacle).
void expectFreePath(const PlanRequest& r, const std::vector<Eigen::VectorXd>& path) {
  const robot::Scene scene = test::plannedScene(world(), r);
  robot::CollisionChecker checker(world().collisionModel(), scene,
                                  &world().object(scene.target_object)->geometry);
  checker.setSphereTier(false);
  for (std::size_t i = 1; i < path.size(); ++i)
    for (int k = 0; k <= 400; ++k)
      ASSERT_FALSE(checker.inCollision(path[i - 1] + (path[i] - path[i - 1]) * (k / 400.0)))
          << "segment " << i << " at " << k << "/400";
}

TEST(MotionGoals, AJointGoalIsReachedByAFreePath) {
  PlanRequest r = shelfRequest(1);
  const Eigen::VectorXd start = r.scene.startFor(robot().name()).value_or(robot().home());
  const Eigen::VectorXd goal = freeConfiguration(r, start.tail(robot().numHandDofs()), 11);
  r.goals = {JointGoal{goal}};
  const PlanResult result = planGrasp(world(), r);
  ASSERT_TRUE(result.success) << result.message;
  ASSERT_GE(result.path.size(), 2u);
  EXPECT_EQ(result.path.front(), start);
  EXPECT_EQ(result.path.back(), goal);
  EXPECT_EQ(result.reached_goal, 0);
  EXPECT_EQ(result.grasp.hand_configuration.size(), 0) << "a motion plan has no grasp";
  expectFreePath(r, result.path);
  // The trajectory runs from the start to the goal, with no closing.
  ASSERT_FALSE(result.trajectory.points.empty());
  EXPECT_TRUE(result.trajectory.points.front().positions.isApprox(start, 1e-12));
  EXPECT_TRUE(result.trajectory.points.back().positions.isApprox(goal, 1e-9));
  EXPECT_DOUBLE_EQ(result.trajectory.closing_start, result.trajectory.duration);

  // Same seed, same path.
  const PlanResult again = planGrasp(world(), r);
  ASSERT_TRUE(again.success);
  EXPECT_EQ(again.path, result.path);
}

TEST(MotionGoals, AnArmGoalKeepsTheStartsHand) {
  PlanRequest r = shelfRequest(2);
  const Eigen::VectorXd start = r.scene.startFor(robot().name()).value_or(robot().home());
  const Eigen::VectorXd goal = freeConfiguration(r, start.tail(robot().numHandDofs()), 12);
  r.goals = {JointGoal{goal.head(robot().numArmDofs())}};
  const PlanResult result = planGrasp(world(), r);
  ASSERT_TRUE(result.success) << result.message;
  EXPECT_EQ(result.path.back(), goal);
  for (const Eigen::VectorXd& q : result.path)
    EXPECT_EQ(q.tail(robot().numHandDofs()), start.tail(robot().numHandDofs()));
}

TEST(MotionGoals, APoseGoalIsReachedWithinItsTolerances) {
  PlanRequest r = shelfRequest(3);
  const Eigen::VectorXd start = r.scene.startFor(robot().name()).value_or(robot().home());
  const Eigen::VectorXd free = freeConfiguration(r, start.tail(robot().numHandDofs()), 13);
  PoseGoal goal;
  goal.pose = r.scene.robot_base *
              robot::forwardKinematics(robot(), free)[static_cast<std::size_t>(robot().palmLink())];
  goal.position_tolerance = 0.002;
  goal.orientation_tolerance = 0.02;
  r.goals = {goal};
  r.parameters["certify_path"] = "1";
  const PlanResult result = planGrasp(world(), r);
  ASSERT_TRUE(result.success) << result.message;
  EXPECT_EQ(result.reached_goal, 0);
  const Eigen::Isometry3d palm =
      r.scene.robot_base *
      robot::forwardKinematics(robot(),
                               result.path.back())[static_cast<std::size_t>(robot().palmLink())];
  EXPECT_LE((palm.translation() - goal.pose.translation()).norm(), 0.002 + 1e-9);
  EXPECT_LE(Eigen::AngleAxisd(palm.linear().transpose() * goal.pose.linear()).angle(), 0.02 + 1e-9);
  EXPECT_TRUE(satisfies(robot(), r.scene.robot_base, checkGoals(robot(), r.goals, start)[0],
                        result.path.back()));
  EXPECT_EQ(result.path.back().tail(robot().numHandDofs()), start.tail(robot().numHandDofs()));
  // Proven with the transit rule up to the goal itself.
  ASSERT_TRUE(result.clearance.has_value());
  EXPECT_GT(*result.clearance, 0.0);
  const robot::Scene scene = test::plannedScene(world(), r);
  robot::CollisionChecker checker(world().collisionModel(), scene,
                                  &world().object(scene.target_object)->geometry);
  EXPECT_TRUE(robot::certifyPath(checker, world().motionBound(), result.path, {}).free);
  expectFreePath(r, result.path);
}

TEST(MotionGoals, TheFirstReachableGoalOfASetEndsThePlan) {
  PlanRequest r = shelfRequest(4);
  const Eigen::VectorXd start = r.scene.startFor(robot().name()).value_or(robot().home());
  const Eigen::VectorXd hand = start.tail(robot().numHandDofs());
  // Goal 0 puts the arm into the shelf's floor (a1 turned to the shelf,
  // arm stretched down); goal 1 is free.
  Eigen::VectorXd colliding = freeConfiguration(r, hand, 14);
  const robot::Scene scene = test::plannedScene(world(), r);
  robot::CollisionChecker checker(world().collisionModel(), scene,
                                  &world().object(scene.target_object)->geometry);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  while (!checker.inCollision(colliding))
    for (int d = 0; d < robot().numArmDofs(); ++d)
      colliding(d) = robot().lowerLimits()(d) +
                     unit(rng) * (robot().upperLimits()(d) - robot().lowerLimits()(d));
  const Eigen::VectorXd free = freeConfiguration(r, hand, 15);
  r.goals = {JointGoal{colliding}, JointGoal{free}};
  const PlanResult result = planGrasp(world(), r);
  ASSERT_TRUE(result.success) << result.message;
  EXPECT_EQ(result.reached_goal, 1);
  EXPECT_EQ(result.path.back(), free);

  r.goals = {JointGoal{colliding}};
  const PlanResult none = planGrasp(world(), r);
  EXPECT_FALSE(none.success);
  EXPECT_EQ(none.failure, PlanFailure::kGoalInCollision);
  EXPECT_NE(none.message.find("touches"), std::string::npos) << none.message;
}

TEST(MotionGoals, TheObjectIsAnObstacle) {
  // A free configuration with the bottle moved onto its palm collides;
  // without an object it does not.
  PlanRequest r = shelfRequest(6);
  const Eigen::VectorXd start = r.scene.startFor(robot().name()).value_or(robot().home());
  const Eigen::VectorXd goal = freeConfiguration(r, start.tail(robot().numHandDofs()), 16);
  r.goals = {JointGoal{goal}};
  r.object_pose =
      r.scene.robot_base *
      robot::forwardKinematics(robot(), goal)[static_cast<std::size_t>(robot().palmLink())];
  const PlanResult blocked = planGrasp(world(), r);
  EXPECT_EQ(blocked.failure, PlanFailure::kGoalInCollision) << blocked.message;
  EXPECT_NE(blocked.message.find("bottle"), std::string::npos) << blocked.message;

  r.object.clear();
  r.scene.target_object.clear();
  r.object_pose.reset();
  const PlanResult free = planGrasp(world(), r);
  EXPECT_TRUE(free.success) << free.message;
}

TEST(MotionGoals, RacingCopiesPlanToo) {
  PlanRequest r = shelfRequest(7);
  const Eigen::VectorXd start = r.scene.startFor(robot().name()).value_or(robot().home());
  r.goals = {JointGoal{freeConfiguration(r, start.tail(robot().numHandDofs()), 17)}};
  r.parameters["threads"] = "2";
  const PlanResult result = planGrasp(world(), r);
  ASSERT_TRUE(result.success) << result.message;
  expectFreePath(r, result.path);
}

TEST(MotionGoals, AnArmWithoutAHandPlansMotionsOnly) {
  // robots/kr5_sdh/kr5_arm_only.json: no hand map, no grasps.
  const PlanningWorld arm(
      robot::RobotModel::load(test::sourcePath("robots/kr5_sdh/kr5_arm_only.json")),
      world().objects());
  PlanRequest r = shelfRequest(8);
  const Eigen::VectorXd start = r.scene.startFor(robot().name()).value_or(robot().home());
  const Eigen::VectorXd goal = freeConfiguration(r, start.tail(robot().numHandDofs()), 18);
  r.start = start.head(6);
  r.goals = {JointGoal{goal.head(6)}};
  const PlanResult result = planGrasp(arm, r);
  ASSERT_TRUE(result.success) << result.message;
  EXPECT_EQ(result.path.back(), goal.head(6));
  EXPECT_EQ(result.joint_names, arm.robot().dofNames());
  // The same path with the full robot's hand at the held posture is free.
  std::vector<Eigen::VectorXd> full;
  for (const Eigen::VectorXd& q : result.path) {
    Eigen::VectorXd f = start;
    f.head(6) = q;
    full.push_back(f);
  }
  expectFreePath(r, full);
  PoseGoal pose;
  pose.pose =
      r.scene.robot_base *
      robot::forwardKinematics(robot(), goal)[static_cast<std::size_t>(robot().flangeLink())];
  r.goals = {pose};
  const PlanResult posed = planGrasp(arm, r);
  ASSERT_TRUE(posed.success) << posed.message;
  r.goals.clear();
  try {
    planGrasp(arm, r);
    ADD_FAILURE() << "a grasp without a hand";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.field(), "goals");
  }
}

TEST(MotionGoals, AMotionBenchMakerProblemIsPlannedAndItsPathIsFree) {
  // box_panda/0001 of the committed sample (tests/data/mbm) with the MBM
  // Panda: the path ends at the goal and a 1/400 FCL sweep finds it free.
  const PlanningWorld panda(
      robot::RobotModel::load(test::sourcePath("robots/panda_mbm/panda_mbm.json")),
      std::make_shared<const ObjectLibrary>(std::map<std::string, db::ObjectDatabase>{}));
  const std::string dir = "tests/data/mbm/box_panda/";
  const robot::MoveItProblem p =
      robot::loadMoveItProblem(panda.robot(), test::sourcePath(dir + "scene0001.yaml"),
                               test::sourcePath(dir + "request0001.yaml"));
  PlanRequest r;
  r.scene = p.scene;
  r.start = p.start;
  r.goals = {JointGoal{p.goal}};
  r.time_limit = 30.0 * test::sanitizerSlowdown();
  const PlanResult result = planGrasp(panda, r);
  ASSERT_TRUE(result.success) << result.message;
  EXPECT_EQ(result.path.front(), p.start);
  EXPECT_EQ(result.path.back(), p.goal);
  robot::CollisionChecker checker(panda.collisionModel(), p.scene, nullptr);
  checker.setSphereTier(false);
  for (std::size_t i = 1; i < result.path.size(); ++i)
    for (int k = 0; k <= 400; ++k)
      ASSERT_FALSE(checker.inCollision(result.path[i - 1] +
                                       (result.path[i] - result.path[i - 1]) * (k / 400.0)))
          << "segment " << i << " at " << k << "/400";
}

/// Distances to a tree that is everywhere 1 away.
class NoKnowledge : public FreeSpaceDistances {
 public:
  double toNonConnected(const Eigen::VectorXd&) const override { return 1.0; }
  double toConnected(const Eigen::VectorXd&) const override { return 1.0; }
};

TEST(MotionGoals, AJointGoalWhosePathWasRejectedIsHandedOutAgain) {
  // The sampler alone: a free joint goal once, then nothing, then again
  // after the planner rejected the path to it (its tree is gone, and a
  // joint goal has no other configuration).
  PlanRequest r = shelfRequest(9);
  const Eigen::VectorXd start = r.scene.startFor(robot().name()).value_or(robot().home());
  const Eigen::VectorXd goal = freeConfiguration(r, start.tail(robot().numHandDofs()), 19);
  const robot::Scene scene = test::plannedScene(world(), r);
  robot::CollisionChecker checker(world().collisionModel(), scene,
                                  &world().object(scene.target_object)->geometry);
  std::mt19937_64 rng(1);
  MotionGoalSampler sampler(world().ik(), checker, rng, scene.robot_base, {JointGoal{goal}}, start);
  const NoKnowledge knowledge;
  const auto never = [] { return false; };
  const GoalSample first = sampler.sample(knowledge, never);
  ASSERT_EQ(first.kind, GoalKind::kGoal);
  EXPECT_EQ(first.configuration, goal);
  EXPECT_EQ(sampler.goalOf(goal), 0);
  EXPECT_EQ(sampler.sample(knowledge, never).kind, GoalKind::kNone);
  sampler.pathRejected(first);
  const GoalSample again = sampler.sample(knowledge, never);
  ASSERT_EQ(again.kind, GoalKind::kGoal);
  EXPECT_EQ(again.configuration, goal);
  EXPECT_EQ(sampler.sample(knowledge, never).kind, GoalKind::kNone);
}

/// The InvalidArgument field of planGrasp for a request, or "" when none.
std::string rejectedField(const PlanRequest& r) {
  try {
    planGrasp(world(), r);
  } catch (const InvalidArgument& e) {
    return e.field();
  }
  return "";
}

TEST(MotionGoals, MalformedGoalsAreRejectedByField) {
  PlanRequest r = shelfRequest(1);
  r.time_limit = 0.1;
  const Eigen::VectorXd home = robot().home();
  r.goals = {JointGoal{home}, JointGoal{Eigen::VectorXd::Zero(3)}};
  EXPECT_EQ(rejectedField(r), "goals[1].joints");
  Eigen::VectorXd far = home;
  far(0) = 100.0;
  r.goals = {JointGoal{far}};
  EXPECT_EQ(rejectedField(r), "goals[0].joints");
  far(0) = std::nan("");
  r.goals = {JointGoal{far}};
  EXPECT_EQ(rejectedField(r), "goals[0].joints");
  PoseGoal pose;
  pose.link = "finger_1_distal";
  r.goals = {pose};
  EXPECT_EQ(rejectedField(r), "goals[0].link");
  pose.link = "tool0";
  pose.position_tolerance = -1.0;
  r.goals = {pose};
  EXPECT_EQ(rejectedField(r), "goals[0].position_tolerance");
  pose.position_tolerance = 0.001;
  pose.orientation_tolerance = 4.0;
  r.goals = {pose};
  EXPECT_EQ(rejectedField(r), "goals[0].orientation_tolerance");
  pose.orientation_tolerance = 0.01;
  pose.pose.linear() *= 2.0;
  r.goals = {pose};
  EXPECT_EQ(rejectedField(r), "goals[0].pose");
  r.goals = {JointGoal{home}};
  r.validate = true;
  EXPECT_EQ(rejectedField(r), "validate");
  r.validate = false;
  r.algorithm = PlanAlgorithm::kRrtConnect;
  EXPECT_EQ(rejectedField(r), "algorithm");
}

TEST(MotionGoals, APoseOutOfReachHasNoGoal) {
  PlanRequest r = shelfRequest(1);
  r.time_limit = 0.5;
  PoseGoal far;
  far.pose.translation() = r.scene.robot_base * Eigen::Vector3d(5.0, 0.0, 0.5);
  r.goals = {far};
  const PlanResult result = planGrasp(world(), r);
  EXPECT_FALSE(result.success);
  EXPECT_EQ(result.failure, PlanFailure::kNoValidGoal);
  EXPECT_NE(result.message.find("without an IK solution"), std::string::npos) << result.message;
}

}  // namespace
}  // namespace hfts::planner
