#include "grasp/grasp_objective.h"

#include <gtest/gtest.h>

#include "bundled_objects.h"
#include "hand_fixture.h"

namespace hfts::grasp {
namespace {

const HandReachability& reachability() {
  return test::kr5SdhReachability();
}

TEST(GraspObjective, UsesBothQualityAndReachability) {
  const HftsSpace space(test::bundledObjects().at("box"), 3);
  GraspObjective objective(space, reachability());
  const HftsNode node = space.child(space.root(), 1234);
  const GraspEvaluation e = objective.evaluate(node);
  EXPECT_DOUBLE_EQ(e.value, e.quality / (e.reachability + 1e-6));
  EXPECT_EQ(objective.evaluations(), 1u);
  objective.evaluate(node);
  EXPECT_EQ(objective.evaluations(), 1u);  // cached
}

TEST(GraspObjective, CachesEveryNodeOnceAcrossGrowth) {
  const HftsSpace space(test::bundledObjects().at("box"), 3);
  GraspObjective objective(space, reachability());
  // More nodes than the first table holds (1024 slots, at most half full).
  constexpr std::uint64_t kNodes = 3000;
  ASSERT_GE(space.numChildren(space.root()), kNodes);
  std::vector<GraspEvaluation> first;
  for (std::uint64_t i = 0; i < kNodes; ++i)
    first.push_back(objective.evaluate(space.child(space.root(), i)));
  EXPECT_EQ(objective.evaluations(), kNodes);
  for (std::uint64_t i = 0; i < kNodes; ++i) {
    const GraspEvaluation again = objective.evaluate(space.child(space.root(), i));
    EXPECT_EQ(again.value, first[i].value) << i;
    EXPECT_EQ(again.quality, first[i].quality) << i;
  }
  EXPECT_EQ(objective.evaluations(), kNodes);  // nothing evaluated twice
}

}  // namespace
}  // namespace hfts::grasp
