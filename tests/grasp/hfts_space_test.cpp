#include "grasp/hfts_space.h"

#include <gtest/gtest.h>

#include "bundled_objects.h"

namespace hfts::grasp {
namespace {

const db::ObjectDatabase& mug() {
  return test::bundledObjects().at("mug");
}

TEST(HftsSpace, RootHas20CubedChildrenAndLeavesNone) {
  const HftsSpace space(mug(), 3);
  EXPECT_EQ(space.numLevels(), 3);
  EXPECT_EQ(space.numChildren(space.root()), 8000u);
  HftsNode node = space.root();
  while (!space.isLeaf(node)) node = space.child(node, space.numChildren(node) - 1);
  EXPECT_EQ(node.level, 3);
  EXPECT_EQ(space.numChildren(node), 0u);
}

TEST(HftsSpace, ChildIndexAndParentInvertChild) {
  const HftsSpace space(mug(), 3);
  const HftsNode top = space.child(space.root(), 4321);
  EXPECT_EQ(space.childIndex(top), 4321u);
  EXPECT_EQ(space.parent(top), space.root());
  EXPECT_EQ(space.numChildren(top), 64u);  // 4 x 4 x 4 for full partitions
  for (std::uint64_t i = 0; i < space.numChildren(top); ++i) {
    const HftsNode c = space.child(top, i);
    EXPECT_EQ(space.childIndex(c), i);
    EXPECT_EQ(space.parent(c), top);
    // Every child's partitions are subsets of the parent's (exact partition).
    for (int f = 0; f < 3; ++f) {
      const auto& p = mug().levels[0][top.parts[static_cast<std::size_t>(f)]];
      const auto& q = mug().levels[1][c.parts[static_cast<std::size_t>(f)]];
      EXPECT_GE(q.contact_begin, p.contact_begin);
      EXPECT_LE(q.contact_begin + q.contact_count, p.contact_begin + p.contact_count);
    }
  }
  EXPECT_THROW(space.child(top, 64), std::out_of_range);
  EXPECT_THROW(space.parent(space.root()), std::invalid_argument);
}

TEST(HftsSpace, RepresentativeGraspUsesThePartitionsRepresentatives) {
  const HftsSpace space(mug(), 3);
  const HftsNode node = space.child(space.root(), 17);
  const GraspContacts g = space.representative(node);
  for (int f = 0; f < 3; ++f) {
    const auto& part = mug().levels[0][node.parts[static_cast<std::size_t>(f)]];
    EXPECT_EQ(Eigen::Vector3d(g.positions.col(f)),
              Eigen::Vector3d(mug().positions.row(part.representative).transpose()));
    EXPECT_EQ(Eigen::Vector3d(g.outward_normals.col(f)), part.mean_normal);
  }
  EXPECT_THROW(space.representative(space.root()), std::invalid_argument);
  EXPECT_THROW(HftsSpace(mug(), 0), std::invalid_argument);
}

}  // namespace
}  // namespace hfts::grasp
