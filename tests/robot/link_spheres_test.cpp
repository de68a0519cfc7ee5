#include "robot/link_spheres.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "robot_fixture.h"
#include "shape_samples.h"

namespace hfts::robot {
namespace {

using test::surfacePoint;
using Shape = CollisionShape::Type;

CollisionShape shape(Shape type, const Eigen::Vector3d& size,
                     const Eigen::Isometry3d& origin = Eigen::Isometry3d::Identity()) {
  CollisionShape s;
  s.type = type;
  s.size = size;
  s.origin = origin;
  return s;
}

Eigen::Isometry3d tilted(const Eigen::Vector3d& at) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  pose.translation() = at;
  return pose;
}

/// A point inside `s`: a surface point pulled toward the shape's centre.
Eigen::Vector3d interiorPoint(const CollisionShape& s, std::mt19937_64& rng) {
  const double t = std::uniform_real_distribution<double>(0, 1)(rng);
  return s.origin.translation() + t * (surfacePoint(s, rng) - s.origin.translation());
}

bool contains(const LinkSphere& s, const Eigen::Vector3d& p) {
  return (p - s.center).norm() <= s.radius + 1e-12;
}

/// A descent from `node` that keeps to spheres holding p reaches a leaf.
bool treeCovers(const LinkSpheres& link, int node, const Eigen::Vector3d& p) {
  const SphereNode& n = link.tree[static_cast<std::size_t>(node)];
  if (!contains(n.sphere, p)) return false;
  return n.leaf() || treeCovers(link, n.left, p) || treeCovers(link, n.right, p);
}

/// p lies in a leaf sphere, and the tree finds it.
bool covered(const LinkSpheres& link, const Eigen::Vector3d& p) {
  bool inLeaf = false;
  for (const LinkSphere& s : link.spheres) inLeaf = inLeaf || contains(s, p);
  return inLeaf && link.root >= 0 && treeCovers(link, link.root, p);
}

/// Every sampled point of every shape lies in a sphere, and no sampled point
/// of a sphere's surface lies farther from the link than the reported excess.
void expectConservativeAndTight(const Link& link, const LinkSpheres& spheres, double tolerance,
                                int samples) {
  std::mt19937_64 rng(7);
  for (const CollisionShape& s : link.shapes)
    for (int i = 0; i < samples; ++i) {
      const Eigen::Vector3d onSurface = surfacePoint(s, rng), inside = interiorPoint(s, rng);
      ASSERT_TRUE(covered(spheres, onSurface)) << link.name << " surface " << onSurface.transpose();
      ASSERT_TRUE(covered(spheres, inside)) << link.name << " interior " << inside.transpose();
    }
  EXPECT_LE(spheres.excess, tolerance) << link.name;
  std::normal_distribution<double> n;
  for (const LinkSphere& s : spheres.spheres)
    for (int i = 0; i < 200; ++i) {
      const Eigen::Vector3d p =
          s.center + s.radius * Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
      ASSERT_LE(signedDistance(link, p), spheres.excess + 1e-9) << link.name;
    }
}

TEST(LinkSpheres, SignedDistancesOfThePrimitivesAreExact) {
  const CollisionShape box = shape(Shape::kBox, {0.2, 0.4, 0.6});
  EXPECT_NEAR(signedDistance(box, {0, 0, 0}), -0.1, 1e-12);
  EXPECT_NEAR(signedDistance(box, {0.4, 0, 0}), 0.3, 1e-12);
  EXPECT_NEAR(signedDistance(box, {0.4, 0.6, 0}), std::hypot(0.3, 0.4), 1e-12);
  const CollisionShape cylinder = shape(Shape::kCylinder, {0.1, 0.4, 0}, tilted({1, 0, 0}));
  EXPECT_NEAR(signedDistance(cylinder, cylinder.origin * Eigen::Vector3d(0, 0, 0.15)), -0.05,
              1e-12);
  EXPECT_NEAR(signedDistance(cylinder, cylinder.origin * Eigen::Vector3d(0.3, 0, 0.3)),
              std::hypot(0.2, 0.1), 1e-12);
  EXPECT_NEAR(signedDistance(shape(Shape::kSphere, {0.5, 0, 0}), {0, 3, 4}), 4.5, 1e-12);
  EXPECT_EQ(signedDistance(Link{}, {0, 0, 0}), std::numeric_limits<double>::infinity());
}

TEST(LinkSpheres, EveryLinkOfTheBundledRobotIsCoveredWithinTheTolerance) {
  const RobotModel& model = test::kr5Sdh();
  for (const double tolerance : {0.02, 0.01}) {
    const SphereModel spheres = buildSphereModel(model, {tolerance});
    ASSERT_EQ(spheres.links.size(), model.links().size());
    for (std::size_t i = 0; i < model.links().size(); ++i) {
      const Link& link = model.links()[i];
      EXPECT_EQ(link.shapes.empty(), spheres.links[i].spheres.empty()) << link.name;
      expectConservativeAndTight(link, spheres.links[i], tolerance, 1000);
    }
    EXPECT_LE(spheres.maxExcess(), tolerance);
  }
}

TEST(LinkSpheres, CapsulesBecomeAFewSlabs) {
  const RobotModel& model = test::kr5Sdh();
  const SphereModel spheres = buildSphereModel(model, {0.01});
  for (const char* capsule :
       {"link_2", "link_3", "link_4", "link_5", "finger_1_proximal", "thumb_distal"}) {
    const LinkSpheres& link = spheres.links[static_cast<std::size_t>(model.linkIndex(capsule))];
    EXPECT_LE(link.spheres.size(), 20u) << capsule;
  }
  // The depth of a capsule's axis is its radius, also next to the caps.
  const Link& link2 = model.links()[static_cast<std::size_t>(model.linkIndex("link_2"))];
  const CollisionShape& cylinder = link2.shapes.front();
  ASSERT_EQ(cylinder.type, Shape::kCylinder);
  const Eigen::Vector3d nearCap = cylinder.origin * Eigen::Vector3d(0, 0, 0.45 * cylinder.size[1]);
  EXPECT_NEAR(signedDistance(link2, nearCap), -cylinder.size[0], 1e-9);
}

TEST(LinkSpheres, ThinPlatesFatDiscsAndTiltedBoxesAreCovered) {
  Link link;
  link.name = "odd";
  link.shapes = {shape(Shape::kBox, {0.3, 0.2, 0.004}),
                 shape(Shape::kCylinder, {0.12, 0.02, 0}, tilted({0, 0, 0.2})),
                 shape(Shape::kBox, {0.05, 0.07, 0.2}, tilted({0.3, 0, 0}))};
  for (const double tolerance : {0.02, 0.01, 0.004}) {
    const LinkSpheres spheres = coverLink(link, {tolerance});
    expectConservativeAndTight(link, spheres, tolerance, 3000);
  }
  EXPECT_GT(coverLink(link, {0.004}).spheres.size(), coverLink(link, {0.02}).spheres.size());
}

TEST(LinkSpheres, SphereShapesAreKeptAsTheyAre) {
  Link link;
  link.shapes = {shape(Shape::kSphere, {0.03, 0, 0}, tilted({0.1, 0.2, 0.3}))};
  const LinkSpheres spheres = coverLink(link);
  ASSERT_EQ(spheres.spheres.size(), 1u);
  ASSERT_EQ(spheres.tree.size(), 1u);
  EXPECT_EQ(spheres.root, 0);
  EXPECT_TRUE(spheres.tree[0].leaf());
  EXPECT_TRUE(spheres.spheres[0].center.isApprox(Eigen::Vector3d(0.1, 0.2, 0.3)));
  EXPECT_DOUBLE_EQ(spheres.spheres[0].radius, 0.03);
  EXPECT_DOUBLE_EQ(spheres.excess, 0.0);
}

TEST(LinkSpheres, TheSameRobotGivesTheSameSpheres) {
  const SphereModel a = buildSphereModel(test::kr5Sdh()), b = buildSphereModel(test::kr5Sdh());
  ASSERT_EQ(a.numSpheres(), b.numSpheres());
  for (std::size_t i = 0; i < a.links.size(); ++i)
    for (std::size_t k = 0; k < a.links[i].spheres.size(); ++k) {
      EXPECT_EQ(a.links[i].spheres[k].center, b.links[i].spheres[k].center);
      EXPECT_EQ(a.links[i].spheres[k].radius, b.links[i].spheres[k].radius);
    }
}

TEST(LinkSpheres, NonPositiveTolerancesAreRefused) {
  for (const double bad : {0.0, -0.01, std::nan(""), HUGE_VAL})
    EXPECT_THROW(coverLink(Link{}, {bad}), std::invalid_argument) << bad;
}

}  // namespace
}  // namespace hfts::robot
