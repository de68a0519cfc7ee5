#pragma once
// Goal sampling for the multi-tree planner: the C_free-proximity-guided
// HFTS sampler of the paper (Algorithm 2) and the decoupled optimiser it is
// compared with (Sec. II-A / IV).

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <unordered_set>
#include <vector>

#include "grasp/grasp_configurations.h"
#include "grasp/grasp_optimizer.h"
#include "planner/goal_hierarchy_cache.h"
#include "planner/motion_check.h"
#include "planner/parameters.h"
#include "planner/plan_statistics.h"

namespace hfts::planner {

/// The default of min_epsilon (docs/planning.md#what-a-goal-is).
inline constexpr double kDefaultMinEpsilon = 0.002;

enum class GoalKind {
  kNone,         ///< nothing new (the paper's "bottom")
  kGoal,         ///< a stable leaf grasp with a collision-free pre-grasp
  kApproximate,  ///< a collision-free configuration of an inner node or failed leaf
};

/// One answer of a goal sampler.
struct GoalSample {
  GoalKind kind = GoalKind::kNone;
  Eigen::VectorXd configuration;  ///< the pre-grasp (goal) or the approximate goal
  Eigen::VectorXd grasp;          ///< kGoal: the grasp as executed (the hand closed to contact)
  grasp::HftsNode node;           ///< the grasp's HFTS node
  grasp::GraspContacts contacts;  ///< the node's representative contacts (object frame, outward)
  double epsilon = 0.0;           ///< of `contacts`: Q(h) as the search rated it
  double reachability = 0.0;      ///< R(h) (m)
  double fingertip_error = 0.0;
  /// kGoal: how the hand closed (its contacts, the palm it closed at) and
  /// the epsilon at those contacts.
  std::shared_ptr<const grasp::HandClosure> closure;
  double contact_epsilon = 0.0;
};

/// What both samplers share: the object's HFTS, Eq. (1), Phi(h) and the
/// collision checker (all outliving the sampler), the planner's random
/// generator, and what makes a goal.
struct GoalSamplingContext {
  const grasp::HftsSpace* space = nullptr;
  grasp::GraspObjective* objective = nullptr;
  grasp::GraspConfigurator* configurator = nullptr;
  robot::CollisionChecker* checker = nullptr;
  std::mt19937_64* rng = nullptr;
  /// How the closing motion (pre-grasp -> grasp) is checked: sampled at
  /// its resolution with the grasp rule (the fingertips' depth in the
  /// target), and with a bound also proven free under the closing rule
  /// (robot::CertifyRule::kClosing).
  MotionCheck closing;
  /// Largest fingertip-to-contact distance of a goal's planned hand
  /// posture (m): a search-time filter, not what makes a goal.
  double max_fingertip_error = 0.005;
  /// Smallest Ferrari-Canny epsilon at the contacts where the closed hand
  /// touches the object for a goal.
  double min_epsilon = kDefaultMinEpsilon;
  /// Whether a stable leaf without a goal tries the hand's other postures
  /// (GoalSamplingSettings::other_postures).
  bool other_postures = false;
};

/// SAMPLEGOAL of Algorithm 1 (line 11): where the multi-tree planner gets
/// the roots of its backward trees.
class GoalSampler {
 public:
  virtual ~GoalSampler() = default;
  GoalSampler(const GoalSampler&) = delete;
  GoalSampler& operator=(const GoalSampler&) = delete;

  /// One call of SAMPLEGOAL. `stop` is polled between expensive steps (time
  /// limit, cancellation); the call then returns what it has.
  virtual GoalSample sample(const FreeSpaceDistances& knowledge,
                            const std::function<bool()>& stop) = 0;

  const GoalSamplerStatistics& statistics() const { return stats_; }

  /// The planner found a path to `goal` (a goal this sampler handed out)
  /// that failed the final check, and dropped its tree. Nothing by
  /// default (a grasp has other goals); a sampler whose goals are few may
  /// hand the goal out again.
  virtual void pathRejected(const GoalSample& goal) { (void)goal; }

 protected:
  GoalSampler() = default;
  GoalSamplerStatistics stats_;
};

/// The samplers of the paper: HFTS grasps, turned into robot configurations
/// by Phi(h) and labelled (collision-free, goal) here.
class GraspGoalSampler : public GoalSampler {
 public:
  /// Throws std::invalid_argument for a context with a null member or a
  /// resolution or fingertip tolerance that is not > 0.
  explicit GraspGoalSampler(GoalSamplingContext context);

 protected:
  /// Phi(h) for a node, each configuration marked collision-free and, for
  /// a stable leaf whose fingertips reach the contacts and whose closing
  /// motion is free, as a goal.
  /// With `other_postures`, a stable leaf without a goal also gets the
  /// configurations of the hand's other postures (`otherHandsSampled`, when
  /// given, is then set).
  std::vector<CachedConfiguration> configurationsOf(const grasp::HftsNode& node, double epsilon,
                                                    bool* otherHandsSampled = nullptr);
  /// The free configurations of the node's grasp with the other hand
  /// postures that put the fingertips on its contacts, marked as above.
  std::vector<CachedConfiguration> otherHandConfigurationsOf(const grasp::HftsNode& node,
                                                             double epsilon);
  GoalSample describe(const grasp::HftsNode& node, const CachedConfiguration& config,
                      GoalKind kind);
  /// Ferrari-Canny epsilon at the contacts where the closed hand touches.
  double contactQuality(const grasp::HandClosure& closure) const;
  /// Whether a collision-free configuration of a stable leaf is a goal
  /// (CachedConfiguration::goal).
  bool isGoal(const CachedConfiguration& c);
  /// With context.closing's bound: the closing motion proven free (its
  /// queries counted); without: true.
  bool closingProven(const CachedConfiguration& c);
  /// Counts a leaf grasp that gave no goal under its first reason.
  void countRejection(double epsilon, const std::vector<grasp::GraspConfigurations>& postures,
                      const std::vector<CachedConfiguration>& free);

 private:
  /// Sorts Phi(h)'s configurations into free and colliding ones and marks
  /// the goals.
  void label(const grasp::HftsNode& node, double epsilon, const grasp::GraspConfigurations& all,
             std::vector<CachedConfiguration>& free, std::vector<CachedConfiguration>& colliding);

 protected:
  GoalSamplingContext context_;
};

/// Settings of the coupled sampler (paper Fig. 6 and Sec. IV).
struct HftsGoalSamplerOptions {
  RatingWeights weights;
  int samples = 4;           ///< kappa: new configurations per call
  int min_iterations = 20;   ///< i_min
  int max_iterations = 100;  ///< i_max
};

/// Algorithm 2 with the goal hierarchy cache (Algorithms 3 and 4).
class HftsGoalSampler : public GraspGoalSampler {
 public:
  /// Throws std::invalid_argument for kappa < 1 or i_min > i_max or i_min < 0.
  HftsGoalSampler(GoalSamplingContext context, HftsGoalSamplerOptions options);

  GoalSample sample(const FreeSpaceDistances& knowledge,
                    const std::function<bool()>& stop) override;
  const GoalHierarchyCache& cache() const { return cache_; }
  /// The approximate-goal set A (part of the non-connected free space).
  const std::vector<Eigen::VectorXd>& approximateGoals() const { return approximate_; }
  /// SAMPLENULLSPACE(n) (Alg. 2 lines 9-10): for a grasp that has a goal
  /// configuration, a further one not handed out yet (marked returned):
  /// another IK branch, then, once those are used up, a configuration with
  /// another hand posture (computed on first need). nullptr when none is
  /// left or n is kNone. Public for tests; the sampler calls it itself.
  const CachedConfiguration* sampleNullSpace(int node);

 private:
  /// SAMPLENEWCHILD(n_p, i): hill climbing on the uncached children, then Phi.
  int sampleNewChild(int parent, int iterations);
  int iterationsFor(int parent, const FreeSpaceDistances& knowledge);

  HftsGoalSamplerOptions options_;
  GoalHierarchyCache cache_;
  std::vector<Eigen::VectorXd> approximate_;
  std::vector<grasp::HftsNode> approximateNodes_;  // the node of each approximate goal
};

/// The decoupled integration: every call runs the plain HFTS optimiser from
/// the root to a leaf with a fixed number of iterations per level,
/// ignoring reachability and connectability, and returns the leaf's goal
/// configuration when it has one.
class DecoupledGoalSampler : public GraspGoalSampler {
 public:
  /// Throws std::invalid_argument for iterations < 1.
  DecoupledGoalSampler(GoalSamplingContext context, int iterations);

  GoalSample sample(const FreeSpaceDistances& knowledge,
                    const std::function<bool()>& stop) override;

 private:
  int iterations_;
  std::unordered_set<grasp::HftsNode, grasp::HftsNodeHash> explored_;
};

/// What goal sampling is set up with besides its tools (paper Fig. 6 and
/// Sec. IV), taken from the plan's settings (plan_settings.h).
struct GoalSamplingSettings {
  HftsGoalSamplerOptions coupled;     ///< "w_f", "w_c", "n_a", "kappa", "i_min", "i_max"
  int decoupled_iterations = 20;      ///< i of the decoupled sampler ("iterations")
  grasp::ObjectiveOptions objective;  ///< "alpha", "friction", "cone_edges"
  /// Largest fingertip-to-contact distance of a goal's planned hand
  /// posture, m ("max_fingertip_error"): which grasps are worth closing.
  double max_fingertip_error = 0.005;
  /// Smallest Ferrari-Canny epsilon of a goal at the contacts where the
  /// hand, closed from the pre-grasp, touches the object ("min_epsilon").
  double min_epsilon = kDefaultMinEpsilon;
  /// How deep (m) a fingertip may be inside the object at the grasp and
  /// while closing; every other link must stay clear ("max_penetration").
  double max_penetration = robot::kDefaultMaxPenetration;
  /// 1: the HFTS holds only the contacts a fingertip can touch where the
  /// object stands (grasp/contact_mask.h), and a plan fails at once when
  /// those allow no stable grasp; 0: every contact, as in the paper
  /// ("mask_contacts").
  int mask_contacts = 1;
  /// 1: a stable leaf grasp whose first hand posture gives no goal (no arm
  /// IK, colliding, closing blocked) also tries the hand's other postures
  /// for the same contacts (HandReachability::queryAlternatives); 0: one
  /// posture per grasp, as in the paper ("other_postures").
  int other_postures = 0;
  /// 1: the objective ranks a grasp whose hand (palm and fingers as R(h)
  /// places them) meets an obstacle below every grasp whose hand fits
  /// (grasp::GraspObjective::setHandCheck); 0: Eq. (1) alone, as in the
  /// paper. Not a planner setting (the planner's option was deleted on
  /// held-out evidence, docs/planning.md): bench::holdability's search
  /// for any grasp that fits ranks so.
  int hand_clearance = 0;
  /// Palm turns about the line through the contacts that Phi(h) tries for a
  /// hand that may turn about it (a parallel-jaw gripper,
  /// grasp::HandQuery::free_turn): evenly spaced from a random start until
  /// one gives a collision-free configuration, skipping those whose hand
  /// alone meets an obstacle; 1: only R(h)'s palm pose. No effect on other
  /// hands ("palm_turns").
  int palm_turns = 8;
};

/// The range of the decoupled sampler's i ("iterations"), for programs
/// that check a request before planning (hfts-bench's decoupledN).
inline constexpr ParameterRange kDecoupledIterationsRange{1, 1, 100000};

}  // namespace hfts::planner
