#include "planner/goal_sampler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "table_mug.h"

namespace hfts::planner {
namespace {

int cacheIndexOf(const HftsGoalSampler& sampler, const grasp::HftsNode& node) {
  for (std::size_t n = 0; n < sampler.cache().size(); ++n)
    if (sampler.cache().node(static_cast<int>(n)).hfts == node) return static_cast<int>(n);
  return GoalHierarchyCache::kNone;
}

TEST(HftsGoalSampler, NullSpaceGivesTheOtherIkBranchesThenOtherHandPostures) {
  test::TableMug setup;
  HftsGoalSampler sampler(setup.context, {});
  const int handDofs = setup.world.robot().numHandDofs();
  int goals = 0, withOtherHands = 0;
  for (int call = 0; call < 400 && goals < 6; ++call) {
    const GoalSample goal = sampler.sample(setup.knowledge, [] { return false; });
    if (goal.kind != GoalKind::kGoal) continue;
    ++goals;
    SCOPED_TRACE("goal " + std::to_string(goals));
    const int n = cacheIndexOf(sampler, goal.node);
    ASSERT_NE(n, GoalHierarchyCache::kNone);
    ASSERT_FALSE(sampler.cache().node(n).other_hands_sampled);
    const auto firstRound = static_cast<std::size_t>(
        std::count_if(sampler.cache().node(n).configurations.begin(),
                      sampler.cache().node(n).configurations.end(),
                      [](const CachedConfiguration& c) { return c.goal; }));
    std::vector<CachedConfiguration> handed;
    while (const CachedConfiguration* c = sampler.sampleNullSpace(n)) handed.push_back(*c);
    EXPECT_EQ(sampler.sampleNullSpace(n), nullptr);  // used up, and stays so
    EXPECT_TRUE(sampler.cache().node(n).other_hands_sampled);
    ASSERT_GE(handed.size(), firstRound - 1);  // every other IK branch first
    std::vector<Eigen::VectorXd> seen{goal.configuration};
    for (std::size_t i = 0; i < handed.size(); ++i) {
      const CachedConfiguration& c = handed[i];
      EXPECT_TRUE(c.goal && c.returned && c.collision_free);
      EXPECT_LE(c.fingertip_error, setup.context.max_fingertip_error);
      EXPECT_FALSE(setup.checker.inCollision(c.pregrasp)) << i;
      EXPECT_TRUE(std::none_of(seen.begin(), seen.end(),
                               [&](const Eigen::VectorXd& q) { return q == c.pregrasp; }))
          << "configuration " << i << " handed out twice";
      seen.push_back(c.pregrasp);
      const bool otherHand =
          (c.grasp.tail(handDofs) - goal.grasp.tail(handDofs)).cwiseAbs().maxCoeff() > 1e-9;
      EXPECT_EQ(otherHand, i + 1 >= firstRound) << i << ": IK branches come before other hands";
    }
    withOtherHands += handed.size() + 1 > firstRound;
  }
  EXPECT_GE(goals, 6);
  EXPECT_GE(withOtherHands, 1) << "no goal grasp had another hand posture";
}

TEST(HftsGoalSampler, NoNullSpaceWithoutAGoal) {
  test::TableMug setup;
  HftsGoalSampler sampler(setup.context, {});
  EXPECT_EQ(sampler.sampleNullSpace(GoalHierarchyCache::kNone), nullptr);
  EXPECT_EQ(sampler.sampleNullSpace(sampler.cache().root()), nullptr);
  for (int call = 0; call < 20; ++call) sampler.sample(setup.knowledge, [] { return false; });
  for (std::size_t n = 1; n < sampler.cache().size(); ++n) {
    const CacheNode& node = sampler.cache().node(static_cast<int>(n));
    if (std::any_of(node.configurations.begin(), node.configurations.end(),
                    [](const CachedConfiguration& c) { return c.goal; }))
      continue;
    EXPECT_EQ(sampler.sampleNullSpace(static_cast<int>(n)), nullptr);
    EXPECT_FALSE(node.other_hands_sampled) << "searched other hands of a grasp without a goal";
  }
}

}  // namespace
}  // namespace hfts::planner
