#include "planner/configuration_space.h"

#include <gtest/gtest.h>

#include "planner/multi_tree_cbirrt.h"
#include "robot_fixture.h"

namespace hfts::planner {
namespace {

const robot::RobotModel& m() {
  return test::kr5Sdh();
}

Eigen::VectorXd throughTheTable() {
  return (Eigen::VectorXd(13) << 0, 0.6, 0.5, 0, 1.57, 0, 0, -0.2, 0.2, -0.2, 0.2, -0.2, 0.2)
      .finished();
}

TEST(ConfigurationSpace, DistanceIsTheWeightedNormOfEquation3) {
  const WeightedStateSpace space(m());
  Eigen::VectorXd a = m().home(), b = m().home();
  b(0) += 0.3;   // arm, weight 1
  b(12) += 0.4;  // hand, weight 0.25
  const double expected = std::sqrt(1.0 * 0.09 + 0.25 * 0.16);
  EXPECT_DOUBLE_EQ(space.distance(a, b), expected);
  ompl::base::State* sa = space.allocState();
  ompl::base::State* sb = space.allocState();
  space.fromVector(a, sa);
  space.fromVector(b, sb);
  EXPECT_DOUBLE_EQ(space.distance(sa, sb), expected);
  EXPECT_EQ(space.toVector(sb), b);
  space.freeState(sa);
  space.freeState(sb);
}

TEST(ConfigurationSpace, RejectsBadWeights) {
  WeightedStateSpace space(m());
  EXPECT_THROW(space.setWeights(Eigen::VectorXd::Ones(3)), std::invalid_argument);
  Eigen::VectorXd negative = Eigen::VectorXd::Ones(13);
  negative(4) = -1.0;
  EXPECT_THROW(space.setWeights(negative), std::invalid_argument);
}

TEST(ConfigurationSpace, WeightParametersChangeTheOneMetricOfSpaceAndChecker) {
  robot::CollisionChecker checker(test::collisionOf(m()), robot::Scene{}, nullptr);
  const auto si = makeSpaceInformation(m(), checker, 0.02);
  MultiTreeCBiRRT planner(si);
  ASSERT_TRUE(planner.params().setParam("weight_hand", "1"));
  ASSERT_TRUE(planner.params().setParam("weight_arm", "2"));
  const auto& space = *si->getStateSpace()->as<WeightedStateSpace>();
  Eigen::VectorXd expected = Eigen::VectorXd::Ones(13);
  expected.head(6).setConstant(2.0);
  EXPECT_EQ(space.weights(), expected);
  EXPECT_EQ(&space.metric(), &checker.metric());  // one object, not two copies
  EXPECT_FALSE(planner.params().setParam("weight_hand", "-1"));
  EXPECT_EQ(checker.metric().weights(), expected);
}

TEST(ConfigurationSpace, MotionValidatorReportsTheLastValidState) {
  const robot::Scene table = robot::loadScene(test::sourcePath("objects/scenes/table.json"));
  robot::CollisionChecker checker(test::collisionOf(m()), table, nullptr);
  const auto si = makeSpaceInformation(m(), checker, 0.02);
  const auto& space = *si->getStateSpace()->as<WeightedStateSpace>();
  ompl::base::ScopedState<> from(si), to(si), last(si);
  space.fromVector(m().home(), from.get());
  space.fromVector(throughTheTable(), to.get());
  ASSERT_TRUE(si->isValid(from.get()));
  ASSERT_FALSE(si->isValid(to.get()));
  EXPECT_FALSE(si->checkMotion(from.get(), to.get()));
  std::pair<ompl::base::State*, double> lastValid(last.get(), -1.0);
  EXPECT_FALSE(si->getMotionValidator()->checkMotion(from.get(), to.get(), lastValid));
  EXPECT_GE(lastValid.second, 0.0);
  EXPECT_LT(lastValid.second, 1.0);
  EXPECT_TRUE(si->isValid(last.get()));
  EXPECT_TRUE(si->checkMotion(from.get(), last.get()));
}

}  // namespace
}  // namespace hfts::planner
