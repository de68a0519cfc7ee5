#pragma once
// The searches of one plan, internal to the planner library: the
// multi-tree CBiRRT (Algorithm 1) with the coupled goal sampler (Algorithm
// 2) or the decoupled one, each goal it reaches checked in physics with
// physics_check; and the outside baseline, OMPL's RRTConnect towards lazily
// sampled goals.

#include <optional>
#include <vector>

#include "physics/simulate_grasp.h"
#include "plan_problem.h"
#include "planner/goal_sampler.h"
#include "planner/path_smoothing.h"
#include "planner/plan_statistics.h"

namespace hfts::planner {

/// What a search found (a path from the start to a goal's pre-grasp) and
/// how it went.
struct SearchOutcome {
  bool solved = false;
  std::vector<ExploredNode> explored;
  std::vector<Eigen::VectorXd> path;
  PathCheckReport path_check;  ///< the final check of `path`
  GoalSample goal;
  GoalSamplerStatistics goals;
  PlanStatistics stats;
  /// With physics_check: the verdict of the goal the search ended at.
  std::optional<physics::GraspVerdict> verdict;
  /// With a lift: the lift of the goal the search ended at (the goal
  /// check's; the baseline's goals are not checked: none).
  std::optional<LiftPath> lift;
};

/// The lift of a reached goal (p.lift's height): the first straight one
/// free (planLift), else a planned one (plannedLift); none when both are
/// blocked, with what blocked going up in `why`, or when `ptc` ends it.
/// Its proofs' queries are counted in `stats`.
std::optional<LiftPath> liftOf(const Problem& p, const GoalSample& goal, PlanStatistics& stats,
                               const ob::PlannerTerminationCondition& ptc,
                               std::string* why = nullptr);

/// The multi-tree CBiRRT (Algorithm 1) with the coupled goal sampler
/// (Algorithm 2) or the decoupled one.
SearchOutcome searchMultiTree(Problem& p, bool coupled, const ob::PlannerTerminationCondition& ptc);

/// The outside baseline: OMPL's RRTConnect towards lazily sampled
/// decoupled goals.
SearchOutcome searchBaseline(Problem& p, const ob::PlannerTerminationCondition& ptc);

}  // namespace hfts::planner
