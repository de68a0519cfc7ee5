#include "planner/goal_hierarchy_cache.h"

#include <gtest/gtest.h>

#include <cmath>

#include "bundled_objects.h"

namespace hfts::planner {
namespace {

/// Omega and Gamma read off the configuration: Omega = q(0), Gamma = q(1).
class FakeKnowledge : public FreeSpaceDistances {
 public:
  double toNonConnected(const Eigen::VectorXd& q) const override { return q(0); }
  double toConnected(const Eigen::VectorXd& q) const override { return q(1); }
};

CachedConfiguration at(double omega, double gamma) {
  CachedConfiguration c;
  c.pregrasp = Eigen::Vector2d(omega, gamma);
  return c;
}

const grasp::HftsSpace& space() {
  static const grasp::HftsSpace s(test::bundledObjects().at("box"), 3);
  return s;
}

constexpr double kWf = 0.5, kWc = 4.0;

double configRating(double omega, double gamma) {
  return kWf * std::exp(-omega) + kWc * std::exp(-gamma);
}

TEST(GoalHierarchyCache, CoverageIsCachedOverPossibleChildren) {
  GoalHierarchyCache cache(space(), {});
  const grasp::HftsNode root = space().root();
  EXPECT_EQ(cache.coverage(cache.root()), 0.0);
  int child = -1;
  for (std::uint64_t i = 0; i < 3; ++i) child = cache.addChild(0, space().child(root, i), {}, 0.0);
  EXPECT_DOUBLE_EQ(cache.coverage(0), 3.0 / static_cast<double>(space().numChildren(root)));
  // A node whose children are all cached has coverage 1 (the authors' code
  // got this wrong through integer division).
  const grasp::HftsNode level1 = cache.node(child).hfts;
  for (std::uint64_t i = 0; i < space().numChildren(level1); ++i)
    cache.addChild(child, space().child(level1, i), {}, 0.0);
  EXPECT_DOUBLE_EQ(cache.coverage(child), 1.0);
  EXPECT_THROW(cache.addChild(child, space().child(level1, 0), {}, 0.0), std::invalid_argument);
}

TEST(GoalHierarchyCache, RatingFollowsEquation4) {
  GoalHierarchyCache cache(space(), {kWf, kWc, 20});
  const FakeKnowledge k;
  const grasp::HftsNode root = space().root();
  const int a = cache.addChild(0, space().child(root, 0), {at(1.0, 2.0), at(0.5, 3.0)}, 0.1);
  const int b = cache.addChild(0, space().child(root, 1), {}, 0.0);
  EXPECT_DOUBLE_EQ(cache.rating(0, k), kWf);  // the root
  EXPECT_DOUBLE_EQ(cache.rating(a, k), std::max(configRating(1.0, 2.0), configRating(0.5, 3.0)));
  // Without configurations: the parent's rating times its coverage.
  EXPECT_DOUBLE_EQ(cache.rating(b, k), cache.coverage(0) * kWf);
  // A collision-free configuration has Omega = 0: rating >= w_f, the root's.
  const int c = cache.addChild(0, space().child(root, 2), {at(0.0, 100.0)}, 0.0);
  EXPECT_NEAR(cache.rating(c, k), kWf, 1e-12);
}

/// Knowledge that grows by one unit of distance per look at a
/// configuration: the value shows how often its memo was seen.
class CountingKnowledge : public FakeKnowledge {
 public:
  FreeSpaceDistance distances(const Eigen::VectorXd& /*q*/, FreeSpaceMemo& memo) const override {
    ++memo.connected_seen;
    return {0.0, static_cast<double>(memo.connected_seen)};
  }
};

TEST(GoalHierarchyCache, RatingsKeepEachConfigurationsMemoAcrossInvalidations) {
  GoalHierarchyCache cache(space(), {kWf, kWc, 20});
  const CountingKnowledge k;
  const int a = cache.addChild(0, space().child(space().root(), 0), {at(9.0, 9.0)}, 0.1);
  EXPECT_DOUBLE_EQ(cache.rating(a, k), configRating(0.0, 1.0));
  EXPECT_DOUBLE_EQ(cache.rating(a, k), configRating(0.0, 1.0));  // memoised: not asked again
  cache.invalidateRatings();
  EXPECT_DOUBLE_EQ(cache.rating(a, k), configRating(0.0, 2.0));  // the same memo, seen twice
  EXPECT_EQ(cache.node(a).configurations.front().memo.connected_seen, 2u);
}

TEST(GoalHierarchyCache, BranchRatingAveragesActiveChildren) {
  GoalHierarchyCache cache(space(), {kWf, kWc, 20});
  const FakeKnowledge k;
  const grasp::HftsNode root = space().root();
  const int p = cache.addChild(0, space().child(root, 5), {at(2.0, 2.0)}, 0.1);
  const grasp::HftsNode level1 = cache.node(p).hfts;
  const int c1 = cache.addChild(p, space().child(level1, 0), {at(1.0, 1.0)}, 0.1);
  const int c2 = cache.addChild(p, space().child(level1, 1), {at(3.0, 0.5)}, 0.1);
  // Leaves of the branch: T(n) = t(n).
  EXPECT_DOUBLE_EQ(cache.branchRating(c1, k), configRating(1.0, 1.0));
  const double expected =
      0.5 * (configRating(2.0, 2.0) + 0.5 * (configRating(1.0, 1.0) + configRating(3.0, 0.5)));
  EXPECT_DOUBLE_EQ(cache.branchRating(p, k), expected);
  // T_p = (1 - cvr) T and T_c = (1 - |L| / (|L_max| + 1)) T.
  EXPECT_DOUBLE_EQ(cache.stayRating(p, k), (1.0 - cache.coverage(p)) * expected);
  EXPECT_DOUBLE_EQ(cache.descendRating(p, k), expected);  // no cached leaf below yet
  EXPECT_DOUBLE_EQ(cache.descendRating(c2, k), cache.branchRating(c2, k));
  EXPECT_DOUBLE_EQ(cache.node(0).possible_leaves, space().numLeaves(root));
}

TEST(GoalHierarchyCache, DescendRatingShrinksWithCachedLeaves) {
  GoalHierarchyCache cache(space(), {kWf, kWc, 20});
  const FakeKnowledge k;
  grasp::HftsNode n = space().child(space().root(), 7);
  int node = cache.addChild(0, n, {at(1.0, 1.0)}, 0.1);
  const int top = node;
  while (!space().isLeaf(n)) {
    n = space().child(n, 0);
    node = cache.addChild(node, n, {at(1.0, 1.0)}, 0.1);
  }
  // One cached leaf: |L| = 1 in every node of the branch.
  EXPECT_DOUBLE_EQ(cache.descendRating(node, k), 0.5 * cache.branchRating(node, k));
  const double leaves = space().numLeaves(cache.node(top).hfts);
  EXPECT_DOUBLE_EQ(cache.node(top).cached_leaves, 1.0);
  EXPECT_DOUBLE_EQ(cache.descendRating(top, k),
                   (1.0 - 1.0 / (leaves + 1.0)) * cache.branchRating(top, k));
}

TEST(GoalHierarchyCache, PickChildDownSamplesActiveChildrenByInverseRating) {
  // Three active children, N_a = 2: one is removed with probability
  // proportional to 1 / T_c; the weak child (T_c tiny) almost always goes.
  const FakeKnowledge k;
  const double ta = configRating(0.0, 0.0), tb = configRating(0.0, 1.0), tc = configRating(3, 3);
  const double inv = 1 / ta + 1 / tb + 1 / tc;
  int removed[3] = {0, 0, 0};
  constexpr int kTrials = 4000;
  for (int trial = 0; trial < kTrials; ++trial) {
    GoalHierarchyCache cache(space(), {kWf, kWc, 2});
    const grasp::HftsNode root = space().root();
    const int ids[3] = {cache.addChild(0, space().child(root, 0), {at(0.0, 0.0)}, 0.1),
                        cache.addChild(0, space().child(root, 1), {at(0.0, 1.0)}, 0.1),
                        cache.addChild(0, space().child(root, 2), {at(3.0, 3.0)}, 0.1)};
    std::mt19937_64 rng(static_cast<std::uint64_t>(trial));
    const int picked = cache.pickChild(0, k, rng);
    const std::vector<int>& active = cache.node(0).active;
    ASSERT_EQ(active.size(), 2u);
    EXPECT_NE(std::find(active.begin(), active.end(), picked), active.end());
    for (int i = 0; i < 3; ++i)
      removed[i] += std::find(active.begin(), active.end(), ids[i]) == active.end();
  }
  const double expected[3] = {1 / ta / inv, 1 / tb / inv, 1 / tc / inv};
  for (int i = 0; i < 3; ++i) {
    const double sigma = std::sqrt(expected[i] * (1 - expected[i]) / kTrials);
    EXPECT_NEAR(removed[i] / static_cast<double>(kTrials), expected[i], 4 * sigma + 1e-3)
        << "child " << i;
  }
}

TEST(GoalHierarchyCache, PickChildPrefersHighRatings) {
  const FakeKnowledge k;
  GoalHierarchyCache cache(space(), {kWf, kWc, 20});
  const grasp::HftsNode root = space().root();
  const int strong = cache.addChild(0, space().child(root, 0), {at(0.0, 0.0)}, 0.1);
  cache.addChild(0, space().child(root, 1), {at(0.0, 2.0)}, 0.1);
  const double pStrong = configRating(0, 0) / (configRating(0, 0) + configRating(0, 2));
  std::mt19937_64 rng(3);
  int hits = 0;
  constexpr int kTrials = 4000;
  for (int i = 0; i < kTrials; ++i) hits += cache.pickChild(0, k, rng) == strong;
  EXPECT_NEAR(hits / static_cast<double>(kTrials), pStrong,
              4 * std::sqrt(pStrong * (1 - pStrong) / kTrials));
  GoalHierarchyCache empty(space(), {});
  EXPECT_EQ(empty.pickChild(0, k, rng), GoalHierarchyCache::kNone);
}

TEST(GoalHierarchyCache, ShouldDescendFollowsAlgorithm3) {
  const FakeKnowledge k;
  GoalHierarchyCache cache(space(), {kWf, kWc, 20});
  std::mt19937_64 rng(4);
  const grasp::HftsNode root = space().root();
  const int child = cache.addChild(0, space().child(root, 0), {at(0.0, 0.5)}, 0.1);
  EXPECT_FALSE(cache.shouldDescend(0, GoalHierarchyCache::kNone, k, rng));
  // Randomised in proportion to T_p(parent) and T_c(child).
  const double stay = cache.stayRating(0, k), descend = cache.descendRating(child, k);
  int descents = 0;
  constexpr int kTrials = 4000;
  for (int i = 0; i < kTrials; ++i) descents += cache.shouldDescend(0, child, k, rng);
  const double pDescend = descend / (stay + descend);
  EXPECT_NEAR(descents / static_cast<double>(kTrials), pDescend,
              4 * std::sqrt(pDescend * (1 - pDescend) / kTrials) + 1e-3);
  // A fully covered parent always descends to an inner child; never to a leaf.
  const grasp::HftsNode level1 = cache.node(child).hfts;
  int inner = -1;
  for (std::uint64_t i = 0; i < space().numChildren(level1); ++i)
    inner = cache.addChild(child, space().child(level1, i), {}, 0.0);
  EXPECT_TRUE(cache.shouldDescend(child, inner, k, rng));
  const grasp::HftsNode level2 = cache.node(inner).hfts;
  int leaf = -1;
  for (std::uint64_t i = 0; i < space().numChildren(level2); ++i)
    leaf = cache.addChild(inner, space().child(level2, i), {}, 0.0);
  EXPECT_TRUE(cache.isLeaf(leaf));
  EXPECT_FALSE(cache.shouldDescend(inner, leaf, k, rng));
}

TEST(GoalHierarchyCache, RejectsBadWeights) {
  EXPECT_THROW(GoalHierarchyCache(space(), {0.0, 4.0, 20}), std::invalid_argument);
  EXPECT_THROW(GoalHierarchyCache(space(), {0.5, 4.0, 0}), std::invalid_argument);
}

}  // namespace
}  // namespace hfts::planner
