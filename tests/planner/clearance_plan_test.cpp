// The planner parameter `clearance` (docs/planning.md#clearance): every
// returned path keeps it under the clearance rule, by an independent FCL
// distance sweep; a start within it is refused by name.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "clearance_rule.h"
#include "plan_checks.h"
#include "planner/grasp_motion_planner.h"
#include "robot/kinematics.h"

namespace hfts::planner {
namespace {

const PlanningWorld& world() {
  return test::bundledWorld();
}

/// The rule's smallest distance along the path, 400 states per segment; on
/// the last segment with the hand free of the obstacles when
/// `approachHandFree` (the approach to a pre-grasp, which the hand may end
/// near the support).
test::RuleDistance sweep(const PlanRequest& r, const std::vector<Eigen::VectorXd>& path,
                         bool approachHandFree, std::size_t segments) {
  const robot::Scene scene = test::plannedScene(world(), r);
  robot::CollisionChecker checker(world().collisionModel(), scene,
                                  &world().object(scene.target_object)->geometry);
  const test::ClearanceRule rule(world().robot());
  test::RuleDistance nearest;
  for (std::size_t i = 1; i <= segments; ++i)
    for (int k = 0; k <= 400; ++k) {
      const Eigen::VectorXd q = path[i - 1] + (path[i] - path[i - 1]) * (k / 400.0);
      EXPECT_FALSE(checker.inCollision(q)) << "segment " << i << " at " << k << "/400";
      const test::RuleDistance d =
          rule.at(checker, q, false, approachHandFree && i == segments, 0.05);
      if (d.distance < nearest.distance)
        nearest = {d.distance, d.what + " (segment " + std::to_string(i) + ")"};
    }
  return nearest;
}

TEST(ClearancePlans, AGraspPlansPathKeepsTheClearance) {
  // The table's mug with 1 cm of clearance, every motion proven: the
  // sweep finds the path to the pre-grasp 1 cm from everything the rule
  // counts (the hand free of the target, and of the support on the
  // approach's last stretch).
  PlanRequest r = test::bundledSceneRequest("table", "mug", 1, PlanAlgorithm::kCoupled);
  r.parameters["physics_check"] = "0";
  r.parameters["certify_path"] = "1";
  r.parameters["clearance"] = "0.01";
  const PlanResult result = planGrasp(world(), r);
  ASSERT_TRUE(result.success) << result.message;
  ASSERT_GE(result.path.size(), 3u);
  const test::RuleDistance nearest = sweep(r, result.path, true, result.path.size() - 2);
  EXPECT_GE(nearest.distance, 0.01 - 1e-5) << nearest.what;
}

TEST(ClearancePlans, AMotionPlansPathKeepsTheClearanceSampledOrProven) {
  // A joint goal in the shelf with 2 cm of clearance: proven, and sampled
  // at the final resolution (which may miss the clearance between samples
  // by what a step moves the robot, under 5 mm of the arm's 1.1 m lever).
  PlanRequest r = test::bundledSceneRequest("shelf", "bottle", 2, PlanAlgorithm::kCoupled);
  const robot::RobotModel& robot = world().robot();
  Eigen::VectorXd goal = r.scene.startFor(robot.name()).value_or(robot.home());
  goal(0) += 1.2;
  goal(1) -= 0.3;
  r.goals = {JointGoal{goal}};
  {
    const robot::Scene scene = test::plannedScene(world(), r);
    robot::CollisionChecker checker(world().collisionModel(), scene,
                                    &world().object(scene.target_object)->geometry);
    ASSERT_GT(test::ClearanceRule(robot).at(checker, goal).distance, 0.03);
  }
  r.parameters["clearance"] = "0.02";
  for (const bool proven : {true, false}) {
    SCOPED_TRACE(proven ? "proven" : "sampled");
    r.parameters["certify_path"] = proven ? "1" : "0";
    const PlanResult result = planGrasp(world(), r);
    ASSERT_TRUE(result.success) << result.message;
    const test::RuleDistance nearest = sweep(r, result.path, false, result.path.size() - 1);
    EXPECT_GE(nearest.distance, proven ? 0.02 - 1e-5 : 0.015) << nearest.what;
  }
}

TEST(ClearancePlans, AStartWithinTheClearanceIsRefusedByName) {
  // The table scene's start keeps about 5 cm (the thumb from the table):
  // asked for 10 cm, the plan is refused before any search.
  PlanRequest r = test::bundledSceneRequest("table", "mug", 1, PlanAlgorithm::kCoupled);
  r.parameters["clearance"] = "0.1";
  r.time_limit = 5.0;
  const PlanResult result = planGrasp(world(), r);
  EXPECT_FALSE(result.success);
  EXPECT_EQ(result.failure, PlanFailure::kStartInCollision);
  EXPECT_NE(result.message.find("within the clearance (0.100000 m)"), std::string::npos)
      << result.message;
}

}  // namespace
}  // namespace hfts::planner
