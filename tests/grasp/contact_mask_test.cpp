#include "grasp/contact_mask.h"

#include <gtest/gtest.h>

#include <random>

#include "bundled_objects.h"
#include "core/invalid_argument.h"
#include "grasp/grasp_quality.h"
#include "min_norm_point.h"
#include "robot/fingertip_geometry.h"
#include "robot_fixture.h"

namespace hfts::grasp {
namespace {

constexpr double kPad = 0.014;  // the SDH's pad radius

const db::ObjectDatabase& box() {
  return test::bundledObjects().at("box");  // 8 x 6 x 12 cm, bottom at z = 0
}

robot::Obstacle slab(const std::string& name, const Eigen::Vector3d& size,
                     const Eigen::Vector3d& center) {
  robot::Obstacle o;
  o.name = name;
  o.size = size;
  o.pose.translation() = center;
  return o;
}

/// The box resting on a table (top at z = 0), at the origin.
robot::Scene onTable() {
  robot::Scene s;
  s.obstacles.push_back(slab("table", {1, 1, 0.04}, {0, 0, -0.021}));
  s.target_object = "box";
  return s;
}

TEST(FingertipGeometry, ThePadRadiusIsTheFingerCylinders) {
  for (const robot::Fingertip& tip : test::kr5Sdh().fingertips())
    EXPECT_NEAR(robot::padRadius(test::kr5Sdh(), tip), kPad, 1e-4) << tip.name;
}

TEST(ContactMask, ContactsTooLowForAFingertipAreMasked) {
  const robot::Scene scene = onTable();
  robot::CollisionChecker checker(test::collisionOf(test::kr5Sdh()), scene, &box().geometry);
  const std::vector<bool> usable =
      fingertipReachableContacts(box(), scene.target_pose, checker.scene(), kPad);
  ASSERT_EQ(usable.size(), box().numContacts());
  int masked = 0;
  for (std::size_t i = 0; i < usable.size(); ++i) {
    const Eigen::Vector3d p = box().positions.row(static_cast<Eigen::Index>(i)).transpose();
    const Eigen::Vector3d n = box().normals.row(static_cast<Eigen::Index>(i)).transpose();
    // The sphere's lowest point: the table top is 1 mm below the box.
    const double clearance = (p + kPad * n).z() - (kPad - kContactMaskClearance) + 0.001;
    if (std::abs(clearance) < 1e-4) continue;  // at the border: either answer is right
    EXPECT_EQ(usable[i], clearance > 0.0) << "contact " << i << " at height " << p.z();
    masked += !usable[i];
  }
  EXPECT_GT(masked, 0);  // the bottom face and the lowest 1.3 cm of the sides
}

TEST(ContactMask, AFreeStandingObjectKeepsEveryContact) {
  robot::Scene scene = onTable();
  scene.obstacles.clear();
  robot::CollisionChecker checker(test::collisionOf(test::kr5Sdh()), scene, &box().geometry);
  const std::vector<bool> usable =
      fingertipReachableContacts(box(), scene.target_pose, checker.scene(), kPad);
  EXPECT_EQ(std::count(usable.begin(), usable.end(), true),
            static_cast<std::ptrdiff_t>(box().numContacts()));
  EXPECT_THROW(fingertipReachableContacts(box(), scene.target_pose, checker.scene(), 0.0005),
               InvalidArgument);
}

TEST(MaskedHftsSpace, NoNodeUsesAPartitionWithoutUsableContacts) {
  const robot::Scene scene = onTable();
  robot::CollisionChecker checker(test::collisionOf(test::kr5Sdh()), scene, &box().geometry);
  const std::vector<bool> usable =
      fingertipReachableContacts(box(), scene.target_pose, checker.scene(), kPad);
  const HftsSpace masked(box(), 3, &usable);
  EXPECT_LT(masked.usableContacts(), box().numContacts());
  EXPECT_LT(masked.numChildren(masked.root()), 8000u);
  const auto holdsUsable = [&](int level, std::uint32_t part) {
    const db::HierarchyNode& n = box().levels[static_cast<std::size_t>(level - 1)][part];
    for (std::uint32_t i = n.contact_begin; i < n.contact_begin + n.contact_count; ++i)
      if (usable[i]) return true;
    return false;
  };
  std::mt19937_64 rng(3);
  for (int walk = 0; walk < 300; ++walk) {
    HftsNode node = masked.root();
    while (!masked.isLeaf(node)) {
      const std::uint64_t n = masked.numChildren(node);
      ASSERT_GT(n, 0u);
      const HftsNode child =
          masked.child(node, std::uniform_int_distribution<std::uint64_t>(0, n - 1)(rng));
      EXPECT_EQ(masked.parent(child), node);
      EXPECT_EQ(masked.child(node, masked.childIndex(child)), child);
      node = child;
      for (int f = 0; f < 3; ++f)
        ASSERT_TRUE(holdsUsable(node.level, node.parts[static_cast<std::size_t>(f)]));
      // The representative is a usable contact of the partition.
      const GraspContacts g = masked.representative(node);
      for (int f = 0; f < 3; ++f) {
        bool found = false;
        const db::HierarchyNode& part = box().levels[static_cast<std::size_t>(node.level - 1)]
                                                    [node.parts[static_cast<std::size_t>(f)]];
        for (std::uint32_t i = part.contact_begin; i < part.contact_begin + part.contact_count; ++i)
          found |= usable[i] && g.positions.col(f).isApprox(
                                    box().positions.row(static_cast<Eigen::Index>(i)).transpose());
        EXPECT_TRUE(found) << "finger " << f << " on level " << node.level;
        EXPECT_NEAR(g.outward_normals.col(f).norm(), 1.0, 1e-12);
      }
    }
  }
  // Leaves counted alike by numLeaves and leafContacts.
  EXPECT_DOUBLE_EQ(masked.numLeaves(masked.root()),
                   std::pow(static_cast<double>(masked.leafContacts().positions.cols()), 3));
}

TEST(MaskedHftsSpace, AMaskWithEveryContactChangesNothing) {
  const std::vector<bool> all(box().numContacts(), true);
  const HftsSpace plain(box(), 3), masked(box(), 3, &all);
  std::mt19937_64 rng(4);
  for (int i = 0; i < 200; ++i) {
    const std::uint64_t index = std::uniform_int_distribution<std::uint64_t>(0, 7999)(rng);
    HftsNode a = plain.child(plain.root(), index), b = masked.child(masked.root(), index);
    a = plain.child(a, index % plain.numChildren(a));
    b = masked.child(b, index % masked.numChildren(b));
    ASSERT_EQ(a, b);
    EXPECT_EQ(plain.representative(a).positions, masked.representative(b).positions);
    EXPECT_EQ(plain.representative(a).outward_normals, masked.representative(b).outward_normals);
  }
  const std::vector<bool> tooFew(3, true);
  EXPECT_THROW(HftsSpace(box(), 3, &tooFew), InvalidArgument);
}

TEST(StableGraspPossible, NotWhenOnlyTheTopFaceCanBeTouched) {
  // The box in a tight slot: walls 1 mm from its four sides and the table
  // under it leave the top face, whose normals all point up.
  robot::Scene scene = onTable();
  scene.obstacles.push_back(slab("left", {0.3, 0.02, 0.3}, {0, -0.041 - 0.01, 0.15}));
  scene.obstacles.push_back(slab("right", {0.3, 0.02, 0.3}, {0, 0.041 + 0.01, 0.15}));
  scene.obstacles.push_back(slab("front", {0.02, 0.3, 0.3}, {0.031 + 0.01, 0, 0.15}));
  scene.obstacles.push_back(slab("back", {0.02, 0.3, 0.3}, {-0.031 - 0.01, 0, 0.15}));
  scene.target_pose.linear() =
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();  // 6 x 8 footprint
  robot::CollisionChecker checker(test::collisionOf(test::kr5Sdh()), scene, &box().geometry);
  ASSERT_FALSE(checker.scene().targetTouchesObstacles());
  const std::vector<bool> usable =
      fingertipReachableContacts(box(), scene.target_pose, checker.scene(), kPad);
  const HftsSpace masked(box(), 3, &usable);
  ASSERT_GT(masked.usableContacts(), 0u);
  for (Eigen::Index i = 0; i < masked.leafContacts().outward_normals.cols(); ++i)
    EXPECT_GT((scene.target_pose.linear() * masked.leafContacts().outward_normals.col(i)).z(), 0.9);
  EXPECT_FALSE(stableGraspPossible(masked, {}));
  EXPECT_TRUE(stableGraspPossible(HftsSpace(box(), 3), {}));
  std::vector<bool> none(box().numContacts(), false);
  EXPECT_FALSE(stableGraspPossible(HftsSpace(box(), 3, &none), {}));
}

TEST(DistanceToHull, AgreesWithQhullOnRandomWrenchSets) {
  // Random grasps of 2-5 contacts on a sphere: Qhull's epsilon > 0 exactly
  // when the origin is in the wrenches' hull, i.e. at distance 0.
  std::mt19937_64 rng(11);
  std::normal_distribution<double> gauss;
  int inside = 0, outside = 0;
  for (int trial = 0; trial < 400; ++trial) {
    GraspQualityRequest q;
    const int contacts = 2 + trial % 4;
    q.positions.resize(3, contacts);
    q.normals.resize(3, contacts);
    for (int c = 0; c < contacts; ++c) {
      const Eigen::Vector3d d(gauss(rng), gauss(rng), gauss(rng));
      q.positions.col(c) = 0.05 * d.normalized();
      q.normals.col(c) = -d.normalized();  // inward
    }
    q.torque_scale = 0.05;
    q.use_qhull = true;
    const double epsilon = graspQuality(q).epsilon;
    const double distance = distanceToHull(contactWrenches(q));
    if (epsilon > 1e-9) {
      EXPECT_EQ(distance, 0.0) << "trial " << trial;
      ++inside;
    } else if (distance > 0.0) {
      ++outside;
    }
    // A positive distance always means no force closure.
    if (distance > 0.0) {
      EXPECT_EQ(epsilon, 0.0) << "trial " << trial;
    }
  }
  EXPECT_GT(inside, 50);
  EXPECT_GT(outside, 50);
}

TEST(DistanceToHull, IsTheNearestPointsLength) {
  Eigen::MatrixXd square(2, 4);
  square << 1, 2, 1, 2,  //
      -1, -1, 1, 1;      // x in [1, 2], y in [-1, 1]: nearest point (1, 0)
  EXPECT_NEAR(distanceToHull(square), 1.0, 1e-12);
  square.row(0).array() -= 1.5;  // now around the origin
  EXPECT_EQ(distanceToHull(square), 0.0);
  Eigen::MatrixXd segment(3, 2);
  segment << 1, 1, 1, 1, -1, 3;  // from (1, 1, -1) to (1, 1, 3)
  EXPECT_NEAR(distanceToHull(segment), std::sqrt(2.0), 1e-12);
}

}  // namespace
}  // namespace hfts::grasp
