#pragma once
// The outside baseline of the experiments (docs/planning.md,
// docs/benchmarks.md): what a MoveIt-style user would assemble from OMPL
// instead of the paper's planner. OMPL's RRTConnect plans towards an
// ompl::base::GoalLazySamples region; OMPL's goal sampling thread runs the
// decoupled HFTS optimiser and Phi(h) (DecoupledGoalSampler) and adds the
// pre-grasp of every goal it finds as a goal state. The path then goes
// through the same smoothing and dense re-check as the multi-tree planner's
// (path_smoothing.h). Include only where OMPL is used.

#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/SpaceInformation.h>

#include <Eigen/Core>

#include <cstdint>
#include <vector>

#include "planner/goal_sampler.h"
#include "planner/path_smoothing.h"
#include "planner/planning_world.h"

namespace hfts::planner {

/// The baseline's settings; the request's planner parameters of the same
/// names set them (see planGrasp).
struct LazyGoalSettings {
  /// The decoupled sampler's: i per HFTS level, Eq. (1), the fingertip
  /// tolerance (the coupled options are unused).
  GoalSamplingSettings goals;
  PathSmoothing smoothing;  ///< also the closing motion's check resolution
  std::uint64_t seed = 1;
};

/// What one solve() found and did.
struct LazyGoalOutcome {
  bool solved = false;
  /// Start, ..., pre-grasp: smoothed (or raw) and through the final check.
  std::vector<Eigen::VectorXd> path;
  PathCheckReport path_check;   ///< what that check found
  GoalSample goal;              ///< the goal the path reaches (kGoal when solved)
  GoalSamplerStatistics goals;  ///< of the sampling thread: GS, VGS, GNS
  /// RRTConnect's: iterations (one uniform sample each), goal_trees (goal
  /// states it took as roots of its goal tree), forward_tree_size (start
  /// tree), backward_tree_nodes (goal tree), rejected_paths, path lengths.
  TreeStatistics trees;
  std::uint64_t objective_evaluations = 0;
  std::uint64_t sampling_collision_checks = 0;  ///< made by the sampling thread
};

/// RRTConnect with lazily sampled HFTS goals. Two threads: the caller's
/// runs RRTConnect with the collision checker behind `si`; OMPL's goal
/// sampling thread gets its own collision checker, HFTS objective, Phi(h)
/// and random generator, so the two share nothing mutable.
class LazyGoalRrtConnect {
 public:
  /// `si` from makeSpaceInformation() on the planning thread's checker (its
  /// weights are copied to the sampling thread's). `world`, `scene`,
  /// `object` and `space` must outlive the object. Throws
  /// InvalidArgument ("parameters.iterations") for iterations < 1.
  LazyGoalRrtConnect(ompl::base::SpaceInformationPtr si, const PlanningWorld& world,
                     const robot::Scene& scene, const db::ObjectDatabase& object,
                     const grasp::HftsSpace& space, LazyGoalSettings settings);

  /// Plans from `start` (collision-free) until a path to a goal passes the
  /// re-check or `ptc` fires. The sampling thread is stopped and joined
  /// before this returns, also when it throws; an exception of the sampling
  /// thread is rethrown here. Deterministic per seed only up to thread
  /// timing: the goal sequence and RRTConnect's samples are seeded, but
  /// which goals exist when RRTConnect asks depends on the scheduler.
  /// `ptc` is evaluated by the sampling thread too (it stops at the limit
  /// by itself), so it must be safe to evaluate concurrently, as OMPL's
  /// timed conditions and a condition reading an atomic flag are.
  LazyGoalOutcome solve(const Eigen::VectorXd& start,
                        const ompl::base::PlannerTerminationCondition& ptc);

 private:
  ompl::base::SpaceInformationPtr si_;
  const PlanningWorld& world_;
  const robot::Scene& scene_;
  const db::ObjectDatabase& object_;
  const grasp::HftsSpace& space_;
  LazyGoalSettings settings_;
};

}  // namespace hfts::planner
