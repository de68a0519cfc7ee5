#include "grasp/graspability.h"

#include <gtest/gtest.h>

#include "bundled_objects.h"
#include "core/invalid_argument.h"
#include "hand_fixture.h"

namespace hfts::grasp {
namespace {

TEST(Graspability, CountsStableAndReachableLeafGrasps) {
  const HftsSpace space(test::bundledObjects().at("cylinder"), 3);
  const HandReachability& hand = test::kr5SdhReachability();
  const Graspability g = graspability(space, hand, hand, {}, 400, 0.005, 7);
  EXPECT_EQ(g.sampled, 400u);
  EXPECT_GT(g.stable, 0u);
  EXPECT_LT(g.stable, 400u);
  EXPECT_GT(g.reachable, 0u);
  EXPECT_LE(g.reachable, g.stable);
  // The same seed, the same answer; a looser tolerance reaches more.
  const Graspability again = graspability(space, hand, hand, {}, 400, 0.005, 7);
  EXPECT_EQ(again.reachable, g.reachable);
  EXPECT_GE(graspability(space, hand, hand, {}, 400, 0.05, 7).reachable, g.reachable);
  // Nothing usable: nothing sampled.
  const std::vector<bool> none(space.database().numContacts(), false);
  EXPECT_EQ(graspability(HftsSpace(space.database(), 3, &none), hand, hand).sampled, 0u);
  EXPECT_THROW(graspability(space, hand, hand, {}, 0), InvalidArgument);
}

}  // namespace
}  // namespace hfts::grasp
