// The HFTS of two and four fingertips with the bundled robots that have
// them (Panda + gripper, UR5e + Allegro-like hand): the structure of the
// space, the ratings of Eq. (1) and free-space graspability.
#include <gtest/gtest.h>

#include <cmath>

#include "bundled_objects.h"
#include "grasp/grasp_objective.h"
#include "grasp/graspability.h"
#include "grasp/hfts_space.h"
#include "robot_fixture.h"

namespace hfts::grasp {
namespace {

struct HandOf {
  const char* config;
  int fingers;
};

/// The robot of a config with its hand map's fast and thorough queries.
struct RobotHand {
  robot::RobotModel model;
  HandReachability fast, thorough;
  explicit RobotHand(const char* config)
      : model(robot::RobotModel::load(test::sourcePath(config))),
        fast(model, buildHandMap(model, handMapOptions(model))),
        thorough(model, buildHandMap(model, handMapOptions(model)), HandQueryOptions::thorough()) {}
};

class HftsFingers : public ::testing::TestWithParam<HandOf> {};

TEST_P(HftsFingers, TheSpaceHasOnePartitionPerFingertipOnEveryLevel) {
  const int m = GetParam().fingers;
  const db::ObjectDatabase& mug = test::bundledObjects().at("mug");
  const HftsSpace space(mug, m);
  EXPECT_EQ(space.fingers(), m);
  EXPECT_EQ(space.numChildren(space.root()), static_cast<std::uint64_t>(std::pow(20, m)));
  const HftsNode top =
      space.child(space.root(), 7 * static_cast<std::uint64_t>(std::pow(20, m - 1)) + 3);
  EXPECT_EQ(space.numChildren(top), static_cast<std::uint64_t>(std::pow(4, m)));
  EXPECT_DOUBLE_EQ(space.numLeaves(top), std::pow(16, m));
  for (std::uint64_t i = 0; i < space.numChildren(top); i += 5) {
    const HftsNode c = space.child(top, i);
    EXPECT_EQ(space.parent(c), top);
    EXPECT_EQ(space.childIndex(c), i);
    const GraspContacts g = space.representative(c);
    ASSERT_EQ(g.positions.cols(), m);
    for (int f = 0; f < m; ++f) {
      const auto& part = mug.levels[1][c.parts[static_cast<std::size_t>(f)]];
      EXPECT_EQ(Eigen::Vector3d(g.positions.col(f)),
                Eigen::Vector3d(mug.positions.row(part.representative).transpose()));
    }
  }
  HftsNode leaf = top;
  while (!space.isLeaf(leaf)) leaf = space.child(leaf, space.numChildren(leaf) / 2);
  EXPECT_EQ(leaf.level, 3);
  EXPECT_EQ(space.representative(leaf).positions.cols(), m);
}

TEST_P(HftsFingers, RatingsFollowEquationOneWithTheRobotsHandAndContactModel) {
  const RobotHand hand(GetParam().config);
  ASSERT_EQ(static_cast<int>(hand.model.fingertips().size()), GetParam().fingers);
  const HftsSpace space(test::bundledObjects().at("box"), GetParam().fingers);
  const ObjectiveOptions options = objectiveOptions(hand.model);
  GraspObjective objective(space, hand.fast, options);
  int stable = 0, reachable = 0;
  for (std::uint64_t i = 0; i < 300; ++i) {
    HftsNode node = space.child(space.root(), (i * 7919) % space.numChildren(space.root()));
    while (!space.isLeaf(node)) node = space.child(node, (i * 31) % space.numChildren(node));
    const GraspEvaluation e = objective.evaluate(node);
    // Q is the hull of the contacts' wrenches under the robot's contact
    // model, for contacts the hand can hold (fit_check: on for every hand).
    const GraspContacts contacts = space.representative(node);
    const GraspQualityRequest request = qualityRequest(space, contacts, options);
    EXPECT_EQ(request.torsional_friction, hand.model.torsionalFriction());
    const bool held =
        options.fit_check == 0 || handFits(contacts, hand.fast.maxFingertipDistance());
    EXPECT_EQ(e.quality, held ? graspQuality(request).epsilon : 0.0);
    EXPECT_GE(e.reachability, 0.0);
    if (options.unstable_by_reach == 0 || e.quality > 0.0) {
      EXPECT_DOUBLE_EQ(e.value, e.quality / (e.reachability + options.alpha));
    } else {
      EXPECT_DOUBLE_EQ(e.value, -(e.reachability + options.alpha));
    }
    stable += e.quality > 0.0;
    reachable += e.quality > 0.0 && e.reachability < 0.005;
  }
  // Two soft or four hard fingers find force closure on a box, and the hand reaches some.
  EXPECT_GT(stable, 0);
  EXPECT_GT(reachable, 0);
  // The same in the service's measure, over uniformly drawn leaves.
  const Graspability g = graspability(space, hand.fast, hand.thorough, options);
  EXPECT_GT(g.reachable, 5u);
  EXPECT_LT(g.reachable, g.sampled);
}

INSTANTIATE_TEST_SUITE_P(Robots, HftsFingers,
                         ::testing::Values(HandOf{"robots/panda_gripper/panda_gripper.json", 2},
                                           HandOf{"robots/ur5e_allegro/ur5e_allegro.json", 4}),
                         [](const ::testing::TestParamInfo<HandOf>& param) {
                           return param.param.fingers == 2 ? std::string("TwoFingertips")
                                                           : std::string("FourFingertips");
                         });

}  // namespace
}  // namespace hfts::grasp
