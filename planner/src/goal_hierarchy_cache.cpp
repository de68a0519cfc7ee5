#include "planner/goal_hierarchy_cache.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/invalid_argument.h"

namespace hfts::planner {

namespace {
constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();
// Ratings are products of exponentials and coverages: keep them strictly
// positive so that every child keeps a chance (paper: T_c(n) > 0 always).
constexpr double kSmallestRating = 1e-12;

/// The HFTS as a goal hierarchy.
class HftsHierarchy final : public GoalHierarchy {
 public:
  explicit HftsHierarchy(const grasp::HftsSpace& space) : space_(space) {}
  grasp::HftsNode root() const override { return space_.root(); }
  bool isLeaf(const grasp::HftsNode& node) const override { return space_.isLeaf(node); }
  std::uint64_t numChildren(const grasp::HftsNode& node) const override {
    return space_.numChildren(node);
  }
  double numLeaves(const grasp::HftsNode& node) const override { return space_.numLeaves(node); }

 private:
  const grasp::HftsSpace& space_;
};
}  // namespace

std::size_t sampleWeighted(const std::vector<double>& weights, std::mt19937_64& rng) {
  if (weights.empty()) throw std::invalid_argument("sampleWeighted: no weights");
  double total = 0.0;
  for (const double w : weights) total += w;
  double u = std::uniform_real_distribution<double>(0.0, total)(rng);
  for (std::size_t i = 0; i < weights.size(); ++i) {
    if (u < weights[i]) return i;
    u -= weights[i];
  }
  return weights.size() - 1;  // rounding at the upper end
}

FreeSpaceDistance FreeSpaceDistances::distances(const Eigen::VectorXd& q,
                                                FreeSpaceMemo& /*memo*/) const {
  return {toNonConnected(q), toConnected(q)};
}

GoalHierarchyCache::GoalHierarchyCache(const grasp::HftsSpace& space, RatingWeights weights)
    : ownShape_(std::make_unique<HftsHierarchy>(space)),
      shape_(ownShape_.get()),
      weights_(weights) {
  addRoot();
}

GoalHierarchyCache::GoalHierarchyCache(const GoalHierarchy& shape, RatingWeights weights)
    : shape_(&shape), weights_(weights) {
  addRoot();
}

void GoalHierarchyCache::addRoot() {
  if (!(weights_.w_f > 0.0) || !(weights_.w_c > 0.0))
    throw InvalidArgument(weights_.w_f > 0.0 ? "parameters.w_c" : "parameters.w_f", "must be > 0");
  if (weights_.max_active < 1) throw InvalidArgument("parameters.n_a", "must be >= 1");
  CacheNode root;
  root.hfts = shape_->root();
  root.possible_leaves = shape_->numLeaves(root.hfts);
  nodes_.push_back(std::move(root));
  t_.push_back(kUnknown);
  T_.push_back(kUnknown);
}

int GoalHierarchyCache::addChild(int parent, const grasp::HftsNode& hfts,
                                 std::vector<CachedConfiguration> configurations, double quality) {
  if (!node(parent).sampled.insert(hfts).second)
    throw std::invalid_argument("goal hierarchy cache: child cached twice");
  CacheNode child;
  child.hfts = hfts;
  child.parent = parent;
  child.configurations = std::move(configurations);
  child.possible_leaves = shape_->numLeaves(hfts);
  child.quality = quality;
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back(std::move(child));
  t_.push_back(kUnknown);
  T_.push_back(kUnknown);
  node(parent).children.push_back(index);
  node(parent).active.push_back(index);
  if (shape_->isLeaf(hfts))
    for (int n = index; n != kNone; n = node(n).parent) node(n).cached_leaves += 1.0;
  return index;
}

double GoalHierarchyCache::coverage(int n) const {
  const double possible = static_cast<double>(shape_->numChildren(node(n).hfts));
  if (possible == 0.0) return 1.0;
  return static_cast<double>(node(n).children.size()) / possible;
}

double GoalHierarchyCache::configurationRating(CachedConfiguration& config,
                                               const FreeSpaceDistances& knowledge) const {
  const FreeSpaceDistance d = knowledge.distances(config.pregrasp, config.memo);
  return weights_.w_f * std::exp(-d.to_non_connected) + weights_.w_c * std::exp(-d.to_connected);
}

double GoalHierarchyCache::rating(int n, const FreeSpaceDistances& knowledge) {
  double& memo = t_[static_cast<std::size_t>(n)];
  if (!std::isnan(memo)) return memo;
  CacheNode& c = node(n);
  if (c.parent == kNone) {
    memo = weights_.w_f;  // Eq. (4), root
  } else if (c.configurations.empty()) {
    memo = coverage(c.parent) * rating(c.parent, knowledge);
  } else {
    memo = 0.0;
    for (CachedConfiguration& config : c.configurations)
      memo = std::max(memo, configurationRating(config, knowledge));
  }
  memo = std::max(memo, kSmallestRating);
  return memo;
}

double GoalHierarchyCache::branchRating(int n, const FreeSpaceDistances& knowledge) {
  double& memo = T_[static_cast<std::size_t>(n)];
  if (!std::isnan(memo)) return memo;
  const double own = rating(n, knowledge);
  const std::vector<int>& active = node(n).active;
  if (active.empty()) return memo = own;
  double sum = 0.0;
  for (const int child : active) sum += branchRating(child, knowledge);
  // T_ may have grown no further (no insertions happen while rating), so
  // the reference taken above is still valid.
  return memo = 0.5 * (own + sum / static_cast<double>(active.size()));
}

double GoalHierarchyCache::stayRating(int n, const FreeSpaceDistances& knowledge) {
  return (1.0 - coverage(n)) * branchRating(n, knowledge);
}

double GoalHierarchyCache::descendRating(int n, const FreeSpaceDistances& knowledge) {
  const CacheNode& c = node(n);
  const double explored = c.cached_leaves / (c.possible_leaves + 1.0);
  return std::max((1.0 - explored) * branchRating(n, knowledge), kSmallestRating);
}

void GoalHierarchyCache::invalidateRatings() {
  std::fill(t_.begin(), t_.end(), kUnknown);
  std::fill(T_.begin(), T_.end(), kUnknown);
}

int GoalHierarchyCache::pickChild(int n, const FreeSpaceDistances& knowledge,
                                  std::mt19937_64& rng) {
  CacheNode& parent = node(n);
  if (parent.children.empty()) return kNone;  // Alg. 4 lines 1-2
  // Line 3: re-activate a random child (a no-op when it is active already).
  const int revived =
      parent
          .children[std::uniform_int_distribution<std::size_t>(0, parent.children.size() - 1)(rng)];
  if (std::find(parent.active.begin(), parent.active.end(), revived) == parent.active.end())
    parent.active.push_back(revived);
  std::vector<double> weights;
  // Lines 4-6: down-sample, removing children with probability ~ 1 / T_c.
  while (static_cast<int>(parent.active.size()) > weights_.max_active) {
    weights.clear();
    for (const int c : parent.active) weights.push_back(1.0 / descendRating(c, knowledge));
    parent.active.erase(parent.active.begin() +
                        static_cast<std::ptrdiff_t>(sampleWeighted(weights, rng)));
  }
  // The active set changed: the branch ratings above n are stale.
  T_[static_cast<std::size_t>(n)] = kUnknown;
  for (int up = parent.parent; up != kNone; up = node(up).parent)
    T_[static_cast<std::size_t>(up)] = kUnknown;
  // Line 7: an active child with probability ~ T_c.
  weights.clear();
  for (const int c : parent.active) weights.push_back(descendRating(c, knowledge));
  return parent.active[sampleWeighted(weights, rng)];
}

bool GoalHierarchyCache::shouldDescend(int parent, int child, const FreeSpaceDistances& knowledge,
                                       std::mt19937_64& rng) {
  if (child == kNone || isLeaf(child)) return false;  // Alg. 3 lines 1-2
  if (coverage(parent) >= 1.0) return true;           // lines 3-4
  const double stay = stayRating(parent, knowledge);
  const double descend = descendRating(child, knowledge);
  const double p = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
  return !(p <= stay / (stay + descend));  // lines 5-8
}

HandedOut descendForGoal(GoalHierarchyCache& cache, const FreeSpaceDistances& knowledge,
                         std::mt19937_64& rng, int samples, const std::function<bool()>& stop,
                         const Algorithm2Steps& steps) {
  int parent = cache.root();
  for (int k = samples; k > 0 && !stop();) {  // line 3
    int child = cache.pickChild(parent, knowledge, rng);
    if (cache.shouldDescend(parent, child, knowledge, rng)) {
      parent = child;
    } else if (cache.coverage(parent) >= 1.0) {  // lines 7-13
      if (child != GoalHierarchyCache::kNone)
        if (const CachedConfiguration* goal = steps.null_space(child)) return {child, goal};
      --k;
    } else {  // lines 14-27
      child = steps.new_child(parent);
      --k;
      if (child == GoalHierarchyCache::kNone) continue;
      CacheNode& created = cache.node(child);
      for (CachedConfiguration& c : created.configurations) {
        if (!c.goal) continue;
        c.returned = true;
        return {child, &c};
      }
      if (!created.configurations.empty() && created.configurations.front().collision_free) {
        steps.approximate(child);
        cache.invalidateRatings();  // A is part of the non-connected free space
      }
    }
  }
  return {};
}

}  // namespace hfts::planner
