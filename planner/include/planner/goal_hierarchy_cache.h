#pragma once
// The goal hierarchy cache G of the paper (Sec. III-B): the local optima
// the goal sampler found on each level of the HFTS, their robot
// configurations, and the ratings that guide the search (Eq. 4 and 5,
// Algorithms 3 and 4).

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <unordered_set>
#include <vector>

#include "grasp/hand_closing.h"
#include "grasp/hfts_space.h"

namespace hfts::planner {

/// Omega and Gamma of one configuration (see FreeSpaceDistances).
struct FreeSpaceDistance {
  double to_non_connected = std::numeric_limits<double>::infinity();
  double to_connected = std::numeric_limits<double>::infinity();
};

/// What a FreeSpaceDistances remembered of one configuration at its last
/// look, so that the next look only has to consider what was added since.
/// Opaque to its owner: keep one per configuration, default-constructed.
struct FreeSpaceMemo {
  FreeSpaceDistance known;
  std::uint64_t non_connected_seen = 0;
  std::uint64_t connected_seen = 0;
  std::uint64_t generation = std::numeric_limits<std::uint64_t>::max();
};

/// What the goal sampler knows about free space (paper Sec. III): the
/// weighted distance of Eq. (3) from a configuration to the nearest known
/// collision-free configuration that is not connected to the start
/// (Omega: backward trees and approximate goals) and to the forward tree
/// (Gamma). Infinity when the set is empty.
class FreeSpaceDistances {
 public:
  virtual ~FreeSpaceDistances() = default;
  virtual double toNonConnected(const Eigen::VectorXd& q) const = 0;
  virtual double toConnected(const Eigen::VectorXd& q) const = 0;
  /// Both distances of q, the same values as the two calls above; an
  /// implementation may use `memo` (kept by the caller for this q between
  /// calls) to avoid searching everything again. This one ignores it.
  virtual FreeSpaceDistance distances(const Eigen::VectorXd& q, FreeSpaceMemo& memo) const;
};

/// The rating constants of Fig. 6.
struct RatingWeights {
  double w_f = 0.5;     ///< non-connected free space weight
  double w_c = 4.0;     ///< connected free space weight
  int max_active = 20;  ///< N_a: active children per node
};

/// A robot configuration stored for a cached node (the set C_n).
struct CachedConfiguration {
  Eigen::VectorXd pregrasp;      ///< the hand opened by the pre-grasp angle
  Eigen::VectorXd grasp;         ///< see GraspConfiguration::grasp
  double fingertip_error = 0.0;  ///< m, see GraspConfiguration
  /// How the hand closed on the object (stable leaves), else null.
  std::shared_ptr<const grasp::HandClosure> closure;
  /// Ferrari-Canny epsilon at the contacts the closed hand touches (0
  /// without a closure or when not every pad touches).
  double contact_epsilon = 0.0;
  bool collision_free = false;
  /// A valid goal: a stable leaf whose free pre-grasp's hand closes to pad
  /// contacts with contact_epsilon >= min_epsilon, the closing motion and
  /// the closed grasp free under the grasp rule, the planned fingertips
  /// within max_fingertip_error of the contacts.
  bool goal = false;
  bool returned = false;  ///< already handed to the motion planner
  FreeSpaceMemo memo;     ///< Omega and Gamma of the pre-grasp at the last rating
};

struct CacheNode {
  grasp::HftsNode hfts;
  int parent = -1;            ///< index of p(n); -1 for the root
  std::vector<int> children;  ///< Ch(n)
  std::vector<int> active;    ///< Ch_a(n), a subset of children
  std::unordered_set<grasp::HftsNode, grasp::HftsNodeHash> sampled;  ///< eta of the children
  std::vector<CachedConfiguration> configurations;                   ///< C_n
  double cached_leaves = 0.0;  ///< |L(n)|: leaves of the branch that are cached
  double possible_leaves = 0.0;
  double quality = 0.0;              ///< epsilon of the node's representative grasp
  bool other_hands_sampled = false;  ///< C_n holds the other hand postures' configurations too
};

/// The shape of a hierarchy the cache grows: its root, how many children
/// and leaves a node has. Nodes are grasp::HftsNode values (a level and up
/// to kMaxFingers indices): the HFTS's own, or another hierarchy's encoded
/// in them (the placements', place_goal_sampler.h).
class GoalHierarchy {
 public:
  virtual ~GoalHierarchy() = default;
  virtual grasp::HftsNode root() const = 0;
  virtual bool isLeaf(const grasp::HftsNode& node) const = 0;
  /// 0 for a leaf.
  virtual std::uint64_t numChildren(const grasp::HftsNode& node) const = 0;
  /// Leaves of the branch rooted at `node` (1 for a leaf).
  virtual double numLeaves(const grasp::HftsNode& node) const = 0;
};

/// The cache and its ratings. Node 0 is the root. Ratings depend on the
/// free-space knowledge, which changes as the planner runs: they are
/// memoised until invalidateRatings().
class GoalHierarchyCache {
 public:
  /// The space must outlive the cache. Throws std::invalid_argument for
  /// non-positive weights or N_a < 1.
  GoalHierarchyCache(const grasp::HftsSpace& space, RatingWeights weights);
  /// The same over another hierarchy (which must outlive the cache).
  GoalHierarchyCache(const GoalHierarchy& shape, RatingWeights weights);

  static constexpr int kNone = -1;  ///< the paper's "bottom": no node
  int root() const { return 0; }
  const CacheNode& node(int n) const { return nodes_[static_cast<std::size_t>(n)]; }
  CacheNode& node(int n) { return nodes_[static_cast<std::size_t>(n)]; }
  std::size_t size() const { return nodes_.size(); }
  bool isLeaf(int n) const { return shape_->isLeaf(node(n).hfts); }
  const RatingWeights& weights() const { return weights_; }

  /// Adds eta = `hfts` (a child of the parent's HFTS node not cached
  /// before) to Ch(parent) and Ch_a(parent) (Alg. 2 lines 18-19).
  int addChild(int parent, const grasp::HftsNode& hfts,
               std::vector<CachedConfiguration> configurations, double quality);

  /// cvr(n): cached children / possible children; 1 for a leaf.
  double coverage(int n) const;

  /// Eq. (4) with the given knowledge; the rating of one configuration is
  /// w_f exp(-Omega) + w_c exp(-Gamma).
  double rating(int n, const FreeSpaceDistances& knowledge);
  /// Eq. (5): (t(n) + mean of T over the active children) / 2; t(n) for a
  /// node without active children.
  double branchRating(int n, const FreeSpaceDistances& knowledge);
  /// T_p(n) = (1 - cvr(n)) T(n): the weight of staying at n.
  double stayRating(int n, const FreeSpaceDistances& knowledge);
  /// T_c(n) = (1 - |L(n)| / (|L_max(n)| + 1)) T(n): the weight of descending to n.
  double descendRating(int n, const FreeSpaceDistances& knowledge);
  void invalidateRatings();

  /// Algorithm 4: re-activates a random child, down-samples Ch_a to N_a
  /// children (removal probability proportional to 1 / T_c) and returns an
  /// active child drawn with probability proportional to T_c; kNone when
  /// n has no children.
  int pickChild(int n, const FreeSpaceDistances& knowledge, std::mt19937_64& rng);
  /// Algorithm 3.
  bool shouldDescend(int parent, int child, const FreeSpaceDistances& knowledge,
                     std::mt19937_64& rng);

 private:
  void addRoot();
  double configurationRating(CachedConfiguration& config,
                             const FreeSpaceDistances& knowledge) const;

  std::unique_ptr<GoalHierarchy> ownShape_;  // the HFTS's, when built from one
  const GoalHierarchy* shape_;
  RatingWeights weights_;
  std::vector<CacheNode> nodes_;
  std::vector<double> t_, T_;  // memoised ratings, NaN = not computed
};

/// A goal configuration Algorithm 2 hands out, and its node.
struct HandedOut {
  int node = GoalHierarchyCache::kNone;
  const CachedConfiguration* goal = nullptr;  ///< marked returned
};

/// What Algorithm 2 asks of the hierarchy it searches.
struct Algorithm2Steps {
  /// SAMPLENULLSPACE(n) (lines 9-10): a further goal configuration of node
  /// n not handed out yet (the callee marks it returned), or null.
  std::function<const CachedConfiguration*(int node)> null_space;
  /// SAMPLENEWCHILD(n_p, i) (lines 15-19): the child cached, or kNone.
  std::function<int(int parent)> new_child;
  /// A new node without a goal whose first configuration is free: its
  /// configuration joins the approximate goals A (lines 23-25); the
  /// ratings are invalidated after.
  std::function<void(int node)> approximate;
};

/// Lines 1-27 of Algorithm 2 (the paper's SAMPLEGOAL) over `cache`: from
/// the root, descend by the ratings (Algorithm 3, children picked by
/// Algorithm 4) until `samples` (kappa) null-space or new-child samples
/// were taken or `stop` returns true; the first goal found is handed out
/// (node kNone: none; the caller then draws from A, lines 28-32).
HandedOut descendForGoal(GoalHierarchyCache& cache, const FreeSpaceDistances& knowledge,
                         std::mt19937_64& rng, int samples, const std::function<bool()>& stop,
                         const Algorithm2Steps& steps);

/// Draws an index with probability proportional to weights[i] (all > 0).
std::size_t sampleWeighted(const std::vector<double>& weights, std::mt19937_64& rng);

}  // namespace hfts::planner
