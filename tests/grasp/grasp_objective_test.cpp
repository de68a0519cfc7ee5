#include "grasp/grasp_objective.h"

#include <gtest/gtest.h>

#include <vector>

#include "bundled_objects.h"
#include "grasp/hand_map_builder.h"
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

TEST(GraspObjective, UnstableByReachRanksUnstableGraspsByReachBelowStableOnes) {
  const HftsSpace space(test::bundledObjects().at("box"), 3);
  ObjectiveOptions options;
  options.unstable_by_reach = 1;
  GraspObjective paper(space, reachability());
  GraspObjective byReach(space, reachability(), options);
  int unstable = 0, stable = 0;
  double lowestStable = 1e300, highestUnstable = -1e300;
  for (std::uint64_t i = 0; i < 400; ++i) {
    const HftsNode node = space.child(space.root(), i * 17);
    const GraspEvaluation a = paper.evaluate(node), b = byReach.evaluate(node);
    EXPECT_EQ(a.quality, b.quality);
    EXPECT_EQ(a.reachability, b.reachability);
    if (a.quality > 0) {
      ++stable;
      EXPECT_EQ(b.value, a.value);  // Eq. (1) unchanged for stable grasps
      lowestStable = std::min(lowestStable, b.value);
    } else {
      ++unstable;
      EXPECT_EQ(a.value, 0.0);
      EXPECT_DOUBLE_EQ(b.value, -(b.reachability + options.alpha));
      highestUnstable = std::max(highestUnstable, b.value);
    }
  }
  ASSERT_GT(stable, 0);
  ASSERT_GT(unstable, 0);
  EXPECT_LT(highestUnstable, 0.0);
  EXPECT_GT(lowestStable, highestUnstable);
}

/// Two contacts (object frame) with outward normals.
GraspContacts pair(const Eigen::Vector3d& a, const Eigen::Vector3d& outA, const Eigen::Vector3d& b,
                   const Eigen::Vector3d& outB) {
  GraspContacts g{Eigen::Matrix3Xd(3, 2), Eigen::Matrix3Xd(3, 2)};
  g.positions << a, b;
  g.outward_normals << outA.normalized(), outB.normalized();
  return g;
}

TEST(HandFits, NeedsContactsWithinTheSpanWhosePadsFaceEachOther) {
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  // Squeezing a 6 cm wide box.
  EXPECT_TRUE(handFits(pair(-0.03 * x, -x, 0.03 * x, x), 0.08));
  EXPECT_FALSE(handFits(pair(-0.03 * x, -x, 0.03 * x, x), 0.05)) << "wider than the span";
  // Inside a cup: the outward normals point at each other, the fingers would have to push apart.
  EXPECT_FALSE(handFits(pair(-0.03 * x, x, 0.03 * x, -x), 0.08));
  // One contact on the far side of the other's surface.
  EXPECT_FALSE(handFits(pair(-0.03 * x, -x, 0.03 * x, -x), 0.08));
  // Three contacts around a centre, normals out: each pad pushes towards the others.
  GraspContacts three{Eigen::Matrix3Xd(3, 3), Eigen::Matrix3Xd(3, 3)};
  for (int i = 0; i < 3; ++i) {
    const double a = 2 * M_PI * i / 3;
    three.outward_normals.col(i) = Eigen::Vector3d(std::cos(a), std::sin(a), 0);
    three.positions.col(i) = 0.03 * three.outward_normals.col(i);
  }
  EXPECT_TRUE(handFits(three, 0.06));
  EXPECT_FALSE(handFits(three, 0.05));
  // The excess over the span is that of the widest pair: sqrt(3) * 3 cm.
  EXPECT_NEAR(spanExcess(three, 0.05), std::sqrt(3.0) * 0.03 - 0.05, 1e-12);
  EXPECT_EQ(spanExcess(three, 0.06), 0.0);
}

TEST(GraspObjective, FitCheckGivesQualityZeroToPairsTheJawsCannotHold) {
  const robot::RobotModel panda =
      robot::RobotModel::load(test::sourcePath("robots/panda_gripper/panda_gripper.json"));
  const HandReachability jaws(panda, buildHandMap(panda, handMapOptions(panda)));
  EXPECT_NEAR(jaws.maxFingertipDistance(), 0.08, 1e-4) << "the Franka Hand's 80 mm stroke";
  ObjectiveOptions checked = objectiveOptions(panda);
  ASSERT_EQ(checked.fit_check, 1) << "on for every hand";
  checked.unstable_by_reach = 1;  // as the planner sets it
  ASSERT_EQ(objectiveOptions(test::kr5Sdh()).fit_check, 1);
  ObjectiveOptions unchecked = checked;
  unchecked.fit_check = 0;
  // The mug (outer diameter 8 cm, 5 mm wall): pairs across its body, its
  // rim and its inside.
  const HftsSpace space(test::bundledObjects().at("mug"), 2);
  GraspObjective fit(space, jaws, checked), plain(space, jaws, unchecked);
  int unfit = 0, kept = 0;
  for (std::uint64_t i = 0; i < 3000; ++i) {
    HftsNode node = space.child(space.root(), (i * 7919) % space.numChildren(space.root()));
    while (!space.isLeaf(node)) node = space.child(node, (i * 31) % space.numChildren(node));
    const GraspEvaluation a = fit.evaluate(node), b = plain.evaluate(node);
    EXPECT_EQ(a.reachability, b.reachability);
    if (!(b.quality > 0.0)) continue;
    if (handFits(space.representative(node), jaws.maxFingertipDistance())) {
      ++kept;
      EXPECT_EQ(a.quality, b.quality);
      EXPECT_EQ(a.value, b.value);
    } else {
      ++unfit;
      EXPECT_EQ(a.quality, 0.0) << "force closure the jaws cannot apply";
      // Ranked by reach, each fingertip at least half the excess off.
      const double excess = spanExcess(space.representative(node), jaws.maxFingertipDistance());
      EXPECT_DOUBLE_EQ(a.value, -(std::max(a.reachability, excess / 2) + checked.alpha));
    }
  }
  EXPECT_GT(kept, 10);
  EXPECT_GT(unfit, 10);
}

TEST(GraspObjective, FitClearanceLeavesTheJawsRoomToComeIn) {
  const robot::RobotModel panda =
      robot::RobotModel::load(test::sourcePath("robots/panda_gripper/panda_gripper.json"));
  const HandReachability jaws(panda, buildHandMap(panda, handMapOptions(panda)));
  const double span = jaws.maxFingertipDistance();
  ObjectiveOptions tight = objectiveOptions(panda), roomy = tight;
  roomy.fit_clearance = 0.0025;
  // Across the mug's 8 cm body: at the stroke, and 2.5 mm inside it per side.
  const HftsSpace space(test::bundledObjects().at("mug"), 2);
  GraspObjective atStroke(space, jaws, tight), withRoom(space, jaws, roomy);
  int wide = 0, narrow = 0;
  for (std::uint64_t i = 0; i < 3000; ++i) {
    HftsNode node = space.child(space.root(), (i * 7919) % space.numChildren(space.root()));
    while (!space.isLeaf(node)) node = space.child(node, (i * 31) % space.numChildren(node));
    const GraspContacts c = space.representative(node);
    const double d = (c.positions.col(1) - c.positions.col(0)).norm();
    const GraspEvaluation a = atStroke.evaluate(node), b = withRoom.evaluate(node);
    if (!(a.quality > 0.0)) continue;
    if (d > span - 0.005) {
      ++wide;
      EXPECT_EQ(b.quality, 0.0) << d;
    } else {
      ++narrow;
      EXPECT_EQ(b.quality, a.quality) << d;
    }
  }
  EXPECT_GT(wide, 5);
  EXPECT_GT(narrow, 5);
  roomy.fit_clearance = -0.001;
  test::expectErrorMentioning<std::invalid_argument>([&] { GraspObjective(space, jaws, roomy); },
                                                     {"ObjectiveOptions::fit_clearance", ">= 0"});
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

TEST(GraspObjective, AHandCheckRanksBlockedHandsBelowEveryHandThatFits) {
  const HftsSpace space(test::bundledObjects().at("box"), 3);
  GraspObjective plain(space, reachability());
  GraspObjective checked(space, reachability());
  // "Blocked" when the palm is on the object's +x side: a check that
  // really reads the answer it is given.
  int asked = 0;
  checked.setHandCheck([&asked](const HandQuery& hand) {
    ++asked;
    EXPECT_EQ(hand.hand_configuration.size(), 7);  // the SDH's joints
    return hand.palm_pose.translation().x() > 0.0;
  });
  std::vector<GraspEvaluation> fitting, blockedOnes;
  int blocked = 0;
  for (std::uint64_t i = 0; i < 400; ++i) {
    const HftsNode node = space.child(space.root(), (37 * i) % space.numChildren(space.root()));
    const GraspEvaluation a = plain.evaluate(node), b = checked.evaluate(node);
    EXPECT_FALSE(a.hand_blocked);
    EXPECT_EQ(b.quality, a.quality);
    EXPECT_EQ(b.reachability, a.reachability);
    if (!b.hand_blocked) {
      EXPECT_EQ(b.value, a.value);
      if (b.quality > 0.0 && b.reachability < 0.05) fitting.push_back(b);
      continue;
    }
    ++blocked;
    EXPECT_DOUBLE_EQ(b.value, b.quality / (b.reachability + 1e-6 + kBlockedHandPenalty));
    blockedOnes.push_back(b);
  }
  EXPECT_EQ(asked, 400);
  EXPECT_GT(blocked, 40);
  EXPECT_LT(blocked, 360);
  // A grasp whose hand fits (R within centimetres) outranks every blocked
  // one of no better quality.
  ASSERT_FALSE(fitting.empty());
  for (const GraspEvaluation& f : fitting)
    for (const GraspEvaluation& b : blockedOnes)
      if (b.quality <= f.quality) {
        EXPECT_LT(b.value, f.value);
      }
  // Setting a check forgets what was evaluated without it.
  checked.setHandCheck({});
  EXPECT_EQ(checked.evaluations(), 0u);
  EXPECT_FALSE(checked.evaluate(space.child(space.root(), 37)).hand_blocked);
}

}  // namespace
}  // namespace hfts::grasp
