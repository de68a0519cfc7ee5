#include "grasp/grasp_optimizer.h"

#include <gtest/gtest.h>

#include "bundled_objects.h"
#include "hand_fixture.h"

namespace hfts::grasp {
namespace {

const HandReachability& reachability() {
  return test::kr5SdhReachability();
}

TEST(GraspOptimizer, ObjectiveNeverDecreasesOverIterations) {
  const HftsSpace space(test::bundledObjects().at("bottle"), 3);
  GraspObjective objective(space, reachability());
  std::mt19937_64 rng(3);
  const ClimbResult r = hillClimb(objective, space.root(), 60, rng);
  ASSERT_TRUE(r.found);
  ASSERT_EQ(r.trace.size(), 60u);
  for (std::size_t i = 1; i < r.trace.size(); ++i) EXPECT_GE(r.trace[i], r.trace[i - 1]);
  EXPECT_DOUBLE_EQ(r.trace.back(), r.evaluation.value);
  EXPECT_GT(r.trace.back(), r.trace.front());  // it climbed
}

TEST(GraspOptimizer, ExcludedChildrenAreNeverReturned) {
  const HftsSpace space(test::bundledObjects().at("box"), 3);
  GraspObjective objective(space, reachability());
  std::mt19937_64 rng(5);
  const HftsNode top = space.child(space.root(), 99);
  std::unordered_set<HftsNode, HftsNodeHash> excluded;
  for (std::uint64_t i = 0; i + 1 < space.numChildren(top); ++i)
    excluded.insert(space.child(top, i));
  const ClimbResult r = hillClimb(objective, top, 20, rng, &excluded);
  ASSERT_TRUE(r.found);
  EXPECT_EQ(space.childIndex(r.best), space.numChildren(top) - 1);
  excluded.insert(r.best);
  EXPECT_FALSE(hillClimb(objective, top, 20, rng, &excluded).found);
}

TEST(GraspOptimizer, EveryBundledObjectYieldsStableReachableLeafGrasps) {
  for (const auto& [name, database] : test::bundledObjects()) {
    SCOPED_TRACE(name);
    const HftsSpace space(database, 3);
    GraspObjective objective(space, reachability());
    std::mt19937_64 rng(6);
    double bestR = 1.0;
    bool stable = false;
    for (int restart = 0; restart < 10 && !(stable && bestR < 0.01); ++restart) {
      const ClimbResult leaf = optimizeToLeaf(objective, 40, rng);
      ASSERT_TRUE(space.isLeaf(leaf.best));
      if (leaf.evaluation.quality > 0) {
        stable = true;
        bestR = std::min(bestR, leaf.evaluation.reachability);
      }
    }
    EXPECT_TRUE(stable);
    EXPECT_LT(bestR, 0.01);  // within a centimetre (RMS, with the normal term)
  }
}

}  // namespace
}  // namespace hfts::grasp
