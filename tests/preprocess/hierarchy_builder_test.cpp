#include <gtest/gtest.h>

#include <numeric>
#include <random>

#include "preprocess/hierarchy_builder.h"

namespace hfts::preprocess {
namespace {

struct Cloud {
  db::Points3 positions, normals;
};

Cloud sphere(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g;
  Cloud c{db::Points3(n, 3), db::Points3(n, 3)};
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d d = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    c.normals.row(i) = d.transpose();
    c.positions.row(i) = 0.05 * d.transpose();
  }
  return c;
}

/// Children of every node partition it exactly; leaves are on the last level.
void expectExactPartition(const Hierarchy& h, std::size_t n) {
  std::vector<std::uint32_t> sorted = h.order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::uint32_t> all(n);
  std::iota(all.begin(), all.end(), 0u);
  EXPECT_EQ(sorted, all);  // order is a permutation
  std::uint32_t cursor = 0;
  for (const auto& node : h.levels.front()) {
    EXPECT_EQ(node.contact_begin, cursor);
    cursor += node.contact_count;
  }
  EXPECT_EQ(cursor, n);
  for (std::size_t l = 0; l + 1 < h.levels.size(); ++l) {
    for (const auto& node : h.levels[l]) {
      ASSERT_GE(node.child_count, 1u);
      std::uint32_t c = node.contact_begin;
      for (std::uint32_t k = 0; k < node.child_count; ++k) {
        const auto& child = h.levels[l + 1].at(node.child_begin + k);
        EXPECT_EQ(child.contact_begin, c);
        EXPECT_GT(child.contact_count, 0u);
        c += child.contact_count;
      }
      EXPECT_EQ(c, node.contact_begin + node.contact_count);
    }
  }
  for (const auto& leaf : h.levels.back()) EXPECT_EQ(leaf.child_count, 0u);
}

TEST(HierarchyBuilder, DefaultBranchingGives20_80_320Nodes) {
  const Cloud c = sphere(6000, 1);
  const Hierarchy h = buildHierarchy(c.positions, c.normals, HierarchyOptions{});
  ASSERT_EQ(h.levels.size(), 3u);
  EXPECT_EQ(h.levels[0].size(), 20u);
  EXPECT_EQ(h.levels[1].size(), 80u);
  EXPECT_EQ(h.levels[2].size(), 320u);
  expectExactPartition(h, 6000);
}

TEST(HierarchyBuilder, RepresentativeIsNearestToTheMeanWithUnitMeanNormal) {
  const Cloud c = sphere(2000, 2);
  const Hierarchy h = buildHierarchy(c.positions, c.normals, HierarchyOptions{});
  db::Points3 p(2000, 3), n(2000, 3);
  for (int i = 0; i < 2000; ++i) {
    p.row(i) = c.positions.row(h.order[i]);
    n.row(i) = c.normals.row(h.order[i]);
  }
  for (const auto& level : h.levels) {
    for (const auto& node : level) {
      const auto block = p.middleRows(node.contact_begin, node.contact_count);
      const Eigen::RowVector3d mean = block.colwise().mean();
      const double best = (block.rowwise() - mean).rowwise().norm().minCoeff();
      EXPECT_DOUBLE_EQ((p.row(node.representative) - mean).norm(), best);
      const Eigen::Vector3d meanNormal =
          n.middleRows(node.contact_begin, node.contact_count).colwise().sum().normalized();
      EXPECT_TRUE(node.mean_normal.isApprox(meanNormal, 1e-12));
    }
  }
}

TEST(HierarchyBuilder, SmallClustersGetOneChildPerContact) {
  const Cloud c = sphere(5, 3);
  HierarchyOptions options;
  options.branching = {20, 4, 4};
  const Hierarchy h = buildHierarchy(c.positions, c.normals, options);
  EXPECT_EQ(h.levels[0].size(), 5u);
  EXPECT_EQ(h.levels[1].size(), 5u);
  EXPECT_EQ(h.levels[2].size(), 5u);
  for (const auto& node : h.levels[1]) EXPECT_EQ(node.child_count, 1u);
  expectExactPartition(h, 5);
}

TEST(HierarchyBuilder, AcceptsAnyBranchingList) {
  const Cloud c = sphere(3000, 4);
  HierarchyOptions options;
  options.branching = {7, 3, 2, 2};
  const Hierarchy h = buildHierarchy(c.positions, c.normals, options);
  EXPECT_EQ(h.levels.size(), 4u);
  EXPECT_EQ(h.levels[3].size(), 7u * 3 * 2 * 2);
  expectExactPartition(h, 3000);
}

TEST(HierarchyBuilder, OpposedNormalsFallBackToTheRepresentativesNormal) {
  db::Points3 p(2, 3), n(2, 3);
  p << 0, 0, 0, 0, 0, 0.001;
  n << 0, 0, 1, 0, 0, -1;
  HierarchyOptions options;
  options.branching = {1};
  const Hierarchy h = buildHierarchy(p, n, options);
  const auto& node = h.levels[0][0];
  EXPECT_NEAR(std::abs(node.mean_normal.z()), 1.0, 1e-12);
}

TEST(HierarchyBuilder, RejectsBadOptions) {
  const Cloud c = sphere(10, 5);
  HierarchyOptions options;
  options.branching = {};
  EXPECT_THROW(buildHierarchy(c.positions, c.normals, options), std::invalid_argument);
  options.branching = {4, 0};
  EXPECT_THROW(buildHierarchy(c.positions, c.normals, options), std::invalid_argument);
  options = HierarchyOptions{};
  options.length_scale = 0.0;
  EXPECT_THROW(buildHierarchy(c.positions, c.normals, options), std::invalid_argument);
}

}  // namespace
}  // namespace hfts::preprocess
