#pragma once
// The multi-tree CBiRRT of the paper (Algorithm 1, Sec. III-A): a forward
// tree from the start, backward trees rooted at goals (B_G) and at
// approximate goals (B_A) that a goal sampler provides, the projection
// heuristic for backward trees, path extraction, shortcut smoothing and a
// dense final re-check. An ompl::base::Planner: its settings come typed
// (applySettings) or by name (params()). Include only where OMPL is used.

#include <ompl/base/Goal.h>
#include <ompl/base/Planner.h>
#include <ompl/datastructures/NearestNeighbors.h>

#include <Eigen/Core>

#include <array>
#include <deque>
#include <functional>
#include <memory>
#include <random>
#include <vector>

#include "planner/backward_projection.h"
#include "planner/configuration_space.h"
#include "planner/goal_sampler.h"
#include "planner/path_smoothing.h"
#include "planner/plan_settings.h"

namespace hfts::planner {

template <typename T>
class ScanNearestNeighbors;  // scan_nearest_neighbors.h

/// The goal of a grasp planning problem: goal configurations are not known
/// up front but produced by a GoalSampler while the planner runs.
class GraspGoal : public ompl::base::Goal {
 public:
  /// The sampler must outlive the goal.
  GraspGoal(const ompl::base::SpaceInformationPtr& si, GoalSampler& sampler);
  /// Always false: a state is a goal only as the root of a goal tree.
  bool isSatisfied(const ompl::base::State* state) const override;
  GoalSampler& sampler() const { return sampler_; }

 private:
  GoalSampler& sampler_;
};

class MultiTreeCBiRRT : public ompl::base::Planner {
 public:
  /// `si` must come from makeSpaceInformation().
  explicit MultiTreeCBiRRT(const ompl::base::SpaceInformationPtr& si);
  ~MultiTreeCBiRRT() override;

  ompl::base::PlannerStatus solve(const ompl::base::PlannerTerminationCondition& ptc) override;
  void clear() override;
  void getPlannerData(ompl::base::PlannerData& data) const override;

  /// The heuristic of Sec. III-A.2 (none: backward trees grow plainly).
  void setProjection(std::shared_ptr<BackwardProjection> projection);
  /// Seeds every random decision of the next solve().
  void setSeed(std::uint64_t seed) { seed_ = seed; }
  /// Whether a goal the trees reached may end the search (e.g. its grasp
  /// holds in physics); a goal it refuses has its tree dropped and the
  /// search goes on. None (the default): every reached goal does.
  using GoalCheck = std::function<bool(const GoalSample&)>;
  void setGoalCheck(GoalCheck check) { goalCheck_ = std::move(check); }
  std::mt19937_64& rng() { return rng_; }
  /// Takes the settings this planner uses: the paper's tree parameters,
  /// local sampling, the collision resolution, smoothing
  /// and the DoF weights when set.
  void applySettings(const PlanSettings& settings);

  // The settings as they stand, also settable by name through params()
  // (checked against the planner's table of ranges, plan_settings.h); the
  // names are in parentheses.
  double getRange() const { return range_; }              ///< step size Delta phi ("step_size")
  double getGoalProbabilityMax() const { return pMax_; }  ///< "p_max"
  double getGoalProbabilityMin() const { return pMin_; }  ///< "p_min"
  double getGoalProbabilityDecay() const { return pW_; }  ///< "p_w"
  double getGoalTreeBias() const { return pGoalTree_; }   ///< "p_goal_tree"
  double getProjectionDistance() const { return dM_; }    ///< D_m ("d_m")
  /// Share of backward extensions that aim near one of the tree's own nodes
  /// instead of at a uniform sample ("p_local").
  double getLocalProbability() const { return pLocal_; }
  /// Half-width of that neighbourhood, rad per joint ("local_radius").
  double getLocalRadius() const { return localRadius_; }
  /// "smoothing_steps" and "final_resolution" (path_smoothing.h): also the
  /// resolution a goal's closing motion is checked at.
  const PathSmoothing& smoothing() const { return smoothing_; }
  /// Proves the returned path's segments free (and goals' closing
  /// motions, through the goal sampler that reads smoothing()) with
  /// `bound`; null: samples them at the final resolution. The bound must
  /// outlive the planner.
  void setCertification(const robot::MotionBound* bound) { smoothing_.final_check.bound = bound; }
  /// The rule the proof of a path's last segment follows: kApproach (into
  /// a pre-grasp, the default) or kTransit (into a motion goal).
  void setLastSegmentRule(robot::CertifyRule rule) { smoothing_.last_rule = rule; }

  /// After a successful solve(): the path from the start to the goal's
  /// pre-grasp (smoothed and re-checked) and the goal it reaches.
  const std::vector<Eigen::VectorXd>& solutionPath() const { return solution_; }
  const GoalSample& reachedGoal() const { return reached_; }
  /// What the final check of that path found.
  const PathCheckReport& pathCheck() const { return pathCheck_; }
  const TreeStatistics& statistics() const { return stats_; }

 private:
  struct Motion;
  struct Tree;
  class Knowledge;
  enum class GrowState { kTrapped, kAdvanced, kReached };
  enum class TreeKind { kForward, kGoal, kApproximate };
  enum class Direction { kForward, kBackward };

  void declareParameters();
  std::unique_ptr<ScanNearestNeighbors<Motion*>> makeNearestNeighbors() const;
  Motion* addMotion(int tree, const Eigen::VectorXd& q, Motion* parent);
  int addTree(TreeKind kind, const Eigen::VectorXd& root);
  void sampleGoal(GoalSampler& sampler, const ompl::base::PlannerTerminationCondition& ptc);
  /// The Eq. (3) weight of all arm (or all hand) DoF.
  void setGroupWeight(bool arm, double weight);
  void setProjectionDistance(double d);
  /// Algorithm 1 line 16: returns the index of a connected backward tree,
  /// or -1; the joining nodes land in `forwardEnd` / `backwardEnd`.
  int extendTrees(const ompl::base::PlannerTerminationCondition& ptc, Motion*& forwardEnd,
                  Motion*& backwardEnd);
  /// ConstrainedExtend of CBiRRT: steps of range_ from the tree's nearest
  /// node towards `target` until reached or trapped.
  GrowState constrainedExtend(Tree& tree, const Eigen::VectorXd& target,
                              const ompl::base::PlannerTerminationCondition& ptc, Motion*& last);
  /// One step of constrainedExtend from `current` near the target of a
  /// backward tree: projected (Sec. III-A.2) when the straight step
  /// collides. False when the extension stops there.
  bool projectedStep(const Eigen::VectorXd& target, Motion*& current, Motion*& last,
                     GrowState& state);
  int pickBackwardTree();
  void mergeIntoForward(int tree, Motion* forwardEnd, Motion* backwardEnd);
  void dropTree(int tree);
  bool extractAndShortcutPath(int tree, Motion* forwardEnd, Motion* backwardEnd,
                              const ompl::base::PlannerTerminationCondition& ptc);
  Eigen::VectorXd sampleUniform();
  /// A configuration within local_radius of a random node of `tree`, in
  /// every joint, clamped to the joint limits.
  Eigen::VectorXd sampleNear(const Tree& tree);
  double distance(const Eigen::Ref<const Eigen::VectorXd>& a,
                  const Eigen::Ref<const Eigen::VectorXd>& b) const;

  /// Configurations of the tree nodes, in large chunks: one allocation per
  /// few thousand nodes instead of one each.
  class ConfigurationArena {
   public:
    /// A copy of q that stays put until clear().
    const double* store(const Eigen::VectorXd& q);
    void clear();

   private:
    static constexpr std::size_t kFirstChunkValues = 1 << 11, kChunkValues = 1 << 16;
    std::vector<std::unique_ptr<double[]>> chunks_;
    std::size_t used_ = 0, capacity_ = 0;  ///< of the last chunk
  };

  WeightedStateSpace& space_;
  Eigen::VectorXd lower_, upper_;  // joint limits
  std::shared_ptr<CollisionMotionValidator> validator_;
  std::shared_ptr<BackwardProjection> projection_;
  GoalCheck goalCheck_;
  std::uint64_t seed_ = 1;
  std::mt19937_64 rng_;

  // Fig. 6 of the paper, and Sec. IV for the step size.
  double range_ = 0.1;
  double pMax_ = 0.9, pMin_ = 0.01, pW_ = 1.2, pGoalTree_ = 0.7;
  double dM_ = 0.4;
  double pLocal_ = 1.0, localRadius_ = 0.8;
  PathSmoothing smoothing_;

  std::deque<Motion> motions_;                // every node of every tree (stable addresses)
  ConfigurationArena configurations_;         // their configurations
  std::vector<std::unique_ptr<Tree>> trees_;  // 0: T_f; others: backward (null once gone)
  std::unique_ptr<ScanNearestNeighbors<Motion*>> nonConnected_;  // all backward tree nodes
  // Changes whenever a node leaves T_f or the non-connected set (merge,
  // dropped tree); in between both only grow, in insertion order, so the
  // goal sampler's distances only look at what is new (Knowledge).
  std::uint64_t generation_ = 0;
  Direction direction_ = Direction::kForward;
  std::vector<Eigen::VectorXd> solution_;
  PathCheckReport pathCheck_;
  /// Steps constrainedExtend checks in one stream, and its scratch line.
  static constexpr std::size_t kLookahead = 8;
  std::array<Eigen::VectorXd, kLookahead + 1> lineScratch_;
  GoalSample reached_;
  TreeStatistics stats_;
};

}  // namespace hfts::planner
