#pragma once
// What a found path goes through before a planner returns it
// (docs/planning.md): straight vertices dropped, a greedy vertex reduction
// and random shortcuts for a counted number of steps from a seeded
// generator, then the final check
// (motion_check.h: every segment proven free, or sampled at the final
// resolution); when a shortcut fails it, a repair that smooths on from a
// batch whose path passed, with shortcuts checked at the final resolution.
// Include only where OMPL is used.

#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/SpaceInformation.h>

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <vector>

#include "planner/configuration_space.h"
#include "planner/motion_check.h"
#include "planner/parameters.h"

namespace hfts::planner {

/// How a path is smoothed and re-checked.
struct PathSmoothing {
  unsigned steps = 200;     ///< shortcut attempts, at most; 0: no smoothing at all
  MotionCheck final_check;  ///< of the returned path; its resolution also the repair's
  std::uint32_t seed = 1;   ///< of the shortcuts' random draws
  /// The proof's rule of the path's last segment: kApproach into a
  /// pre-grasp, kTransit into a motion goal (motion_goal.h).
  robot::CertifyRule last_rule = robot::CertifyRule::kApproach;
};

/// What the final check of a returned path found (smoothAndRecheck).
struct PathCheckReport {
  /// Proven: the smallest distance the proofs of the returned path's
  /// segments measured (m); sampled: none.
  std::optional<double> clearance;
  std::size_t queries = 0;  ///< distance queries of every proof made
  double seconds = 0.0;     ///< wall clock in the final check and the repair's checks
};

/// Shortens `path` on `si`, whose motion validator checks every change:
/// the interior vertices on a straight line between their neighbours are
/// dropped (a tree extension's steps; no check), then a greedy vertex
/// reduction (from each kept vertex straight to the farthest later one
/// reached free), then up to `steps` random shortcuts in batches of 20
/// between which `ptc` is polled, ending after two batches that shortened
/// nothing; a shortcut that would save less than 0.1 % of the path's
/// length is not checked. The vertex reduction starts even when `ptc` has
/// fired (a shorter path is cheaper to re-check). Counted steps, not a time
/// budget, so the seed fixes the result. The end points never move.
std::vector<Eigen::VectorXd> smoothPath(const ompl::base::SpaceInformationPtr& si,
                                        const std::vector<Eigen::VectorXd>& path,
                                        const PathSmoothing& smoothing,
                                        const ompl::base::PlannerTerminationCondition& ptc);

/// True when the path is not empty, its first configuration is free and
/// every segment is free at `resolution` (sampled).
bool denselyValid(const CollisionMotionValidator& validator,
                  const std::vector<Eigen::VectorXd>& path, double resolution);

/// The path a planner returns for `raw` (free at the tree resolution):
/// smoothed with shortcuts checked at the tree resolution if that passes
/// the final check (smoothing.final_check; the last segment under
/// smoothing.last_rule). Else (only while `ptc` allows) repaired: the path after a
/// smoothing batch that passes the check (found by bisection over the
/// batches; `raw` if need be), smoothed on (the vertex reduction and one
/// batch of shortcuts) with every change checked at the final check's
/// resolution. Nothing when
/// `raw` itself fails. The check gives up (nothing, or the last path that
/// passed) 25 ms after `ptc` fires, bounding how far a planner overruns its
/// time limit. The motion validator's resolution is the same afterwards.
/// `report`, when given, gets what the final check found.
std::optional<std::vector<Eigen::VectorXd>> smoothAndRecheck(
    const ompl::base::SpaceInformationPtr& si, const std::vector<Eigen::VectorXd>& raw,
    const PathSmoothing& smoothing, const ompl::base::PlannerTerminationCondition& ptc,
    PathCheckReport* report = nullptr);

/// Sum of the segment lengths in the Eq. (3) metric of `space`.
double pathLength(const WeightedStateSpace& space, const std::vector<Eigen::VectorXd>& path);

}  // namespace hfts::planner
