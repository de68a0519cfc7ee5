#include "robot/pair_maps.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <utility>

#include "robot/kinematics.h"
#include "robot/link_spheres.h"
#include "robot_fixture.h"
#include "shape_samples.h"

namespace hfts::robot {
namespace {

const RobotModel& bundled(const std::string& name) {
  static const RobotModel panda =
      RobotModel::load(test::sourcePath("robots/panda_gripper/panda_gripper.json"));
  static const RobotModel ur5e =
      RobotModel::load(test::sourcePath("robots/ur5e_allegro/ur5e_allegro.json"));
  if (name == "panda_gripper") return panda;
  if (name == "ur5e_allegro") return ur5e;
  return test::kr5Sdh();
}

const PairMap* find(const RobotModel& model, const std::string& a, const std::string& b) {
  const int la = model.linkIndex(a), lb = model.linkIndex(b);
  for (const PairMap& map : test::collisionOf(model).pair_maps)
    if (map.link_a == std::min(la, lb) && map.link_b == std::max(la, lb)) return &map;
  return nullptr;
}

/// The smallest signed distance, at q, from sampled surface points of each
/// link's shapes to the other link's geometry.
double geometryGap(const RobotModel& model, const PairMap& map, const Eigen::VectorXd& q,
                   std::mt19937_64& rng) {
  const LinkPoses poses = forwardKinematics(model, q);
  double gap = std::numeric_limits<double>::infinity();
  for (const auto& [from, to] : {std::pair{map.link_a, map.link_b}, {map.link_b, map.link_a}}) {
    const Eigen::Isometry3d toOther =
        poses[static_cast<std::size_t>(to)].inverse() * poses[static_cast<std::size_t>(from)];
    const Link& other = model.links()[static_cast<std::size_t>(to)];
    for (const CollisionShape& shape : model.links()[static_cast<std::size_t>(from)].shapes)
      for (int i = 0; i < 100; ++i)
        gap = std::min(gap, signedDistance(other, toOther * test::surfacePoint(shape, rng)));
  }
  return gap;
}

Eigen::VectorXd randomConfiguration(const RobotModel& model, std::mt19937_64& rng) {
  Eigen::VectorXd q(model.numDofs());
  for (int d = 0; d < model.numDofs(); ++d)
    q(d) =
        std::uniform_real_distribution<double>(model.lowerLimits()(d), model.upperLimits()(d))(rng);
  return q;
}

// The wrist's forearm and flange turn against each other through a5 and a6
// only, a finger's base and the other finger's proximal link through the
// knuckle and one joint. Pairs through four or more DoFs get no map.
TEST(PairMaps, CoverTheKr5sPairsThroughOneToThreeDofs) {
  const RobotModel& model = test::kr5Sdh();
  const PairMap* wrist = find(model, "link_4", "link_6");
  ASSERT_NE(wrist, nullptr);
  const int a5 =
      model
          .joints()[static_cast<std::size_t>(
              model.links()[static_cast<std::size_t>(model.linkIndex("link_5"))].parent_joint)]
          .dof;
  EXPECT_EQ(wrist->dofs[0], a5);
  EXPECT_EQ(wrist->dofs[1], a5 + 1);
  EXPECT_EQ(wrist->dofs[2], -1);
  EXPECT_EQ(wrist->cells[0] * wrist->cells[1] * wrist->cells[2], 128 * 128);
  // Apart in most of the wrist's range, touching where a5 folds it.
  EXPECT_GT(wrist->apartShare(), 0.5);
  EXPECT_LT(wrist->apartShare(), 1.0);
  const PairMap* fingers = find(model, "finger_1_base", "finger_2_proximal");
  ASSERT_NE(fingers, nullptr);  // the knuckle's DoF and finger 2's proximal joint
  EXPECT_NE(fingers->dofs[1], -1);
  EXPECT_GT(fingers->apartShare(), 0.5);
  const PairMap* flange = find(model, "link_6", "finger_1_base");
  ASSERT_NE(flange, nullptr);  // the knuckle's DoF alone
  EXPECT_EQ(flange->dofs[1], -1);
  EXPECT_EQ(flange->cells[0], 512);
  const PairMap* twoFingers = find(model, "finger_1_proximal", "finger_2_proximal");
  ASSERT_NE(twoFingers, nullptr);  // the knuckle's DoF and both proximal joints
  EXPECT_NE(twoFingers->dofs[2], -1);
  EXPECT_EQ(twoFingers->cells[0] * twoFingers->cells[1] * twoFingers->cells[2], 32 * 32 * 32);
  EXPECT_GT(twoFingers->apartShare(), 0.0);
  EXPECT_EQ(find(model, "link_1", "link_6"), nullptr);                      // a2 .. a6
  EXPECT_EQ(find(model, "finger_1_distal", "finger_2_proximal"), nullptr);  // four DoFs
  for (const PairMap& map : test::collisionOf(model).pair_maps)
    EXPECT_FALSE(model.isCollisionDisabled(map.link_a, map.link_b));
}

// Wherever a map says apart, the two links' shapes at the exact pose are
// apart by the clearance (sampled surfaces against exact distances): at random configurations and
// at cell boundaries, for every pair of the three bundled robots.
TEST(PairMaps, ApartCellsAreApartAtEveryConfigurationInThem) {
  const PairMapOptions defaults;
  for (const std::string name : {"kr5_sdh", "panda_gripper", "ur5e_allegro"}) {
    const RobotModel& model = bundled(name);
    ASSERT_FALSE(test::collisionOf(model).pair_maps.empty()) << name;
    std::mt19937_64 rng(11);
    for (const PairMap& map : test::collisionOf(model).pair_maps) {
      int proven = 0;
      for (int i = 0; i < 400; ++i) {
        Eigen::VectorXd q = randomConfiguration(model, rng);
        if (i % 2 == 1)  // on a cell boundary of each DoF
          for (int d = 0; d < PairMap::kMaxDofs && map.dofs[d] >= 0; ++d) {
            const int cell = std::uniform_int_distribution<int>(0, map.cells[d] - 1)(rng);
            q(map.dofs[d]) = map.lower[d] + cell * map.width[d];
          }
        if (!map.provesApart(q)) continue;
        ++proven;
        ASSERT_GT(geometryGap(model, map, q, rng), defaults.clearance - 1e-9)
            << name << " " << model.links()[static_cast<std::size_t>(map.link_a)].name << "-"
            << model.links()[static_cast<std::size_t>(map.link_b)].name << " at " << q.transpose();
      }
      EXPECT_EQ(proven > 0, map.apartShare() > 0.0);
    }
  }
}

// Outside the limits nothing is proven.
TEST(PairMaps, ProveNothingOutsideTheLimits) {
  const RobotModel& model = test::kr5Sdh();
  const PairMap* wrist = find(model, "link_4", "link_6");
  ASSERT_NE(wrist, nullptr);
  Eigen::VectorXd q = model.home();
  for (const double outside : {wrist->lower[0] - 0.01, model.upperLimits()(wrist->dofs[0]) + 0.01,
                               std::numeric_limits<double>::quiet_NaN()}) {
    q(wrist->dofs[0]) = outside;
    EXPECT_FALSE(wrist->provesApart(q)) << outside;
  }
}

}  // namespace
}  // namespace hfts::robot
