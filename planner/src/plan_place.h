#pragma once
// The place stage of a pick and place (PlanRequest::place,
// docs/placement.md "Placing"), internal to the planner library: from the
// lift's end, the carry to a placement's pre-place (the multi-tree planner
// in the world of the robot holding the object), the descent, the release
// and the retreat.

#include <ompl/base/PlannerTerminationCondition.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "grasp/stable_placements.h"
#include "plan_problem.h"
#include "planner/lift.h"
#include "planner/place_goal.h"
#include "planner/plan_result.h"

namespace hfts::planner {

/// The region and the ways the object may rest there (placeFaces), or why
/// there is none (kNoStablePlacement). Throws InvalidArgument ("place.on",
/// "place.area") for a malformed goal.
struct PlaceTarget {
  PlaceRegion region;
  std::vector<grasp::RestingFace> faces;
};
std::pair<std::optional<PlaceTarget>, std::string> placeTarget(const robot::Scene& scene,
                                                               const db::ObjectDatabase& object,
                                                               const PlaceGoal& goal);

/// What the place stage found.
struct PlaceOutcome {
  std::optional<Placement> placement;
  PlaceRejections rejected;
  std::string why;  ///< without a placement: why not
  /// The carry search's statistics, added to the plan's.
  std::uint64_t iterations = 0;
  std::uint64_t goal_sampling_calls = 0;
  std::uint64_t collision_checks = 0;
  std::size_t certificate_queries = 0;
  /// With a rate: the carry, the descent, the opening and the retreat,
  /// from the lift's end (empty points when its samples could not be made
  /// free); the times (s, from its start) the descent, the opening and the
  /// retreat begin.
  GraspTrajectory trajectory;
  double descent_start = 0.0;
  double release_start = 0.0;
  double retreat_start = 0.0;
};

/// Places the object the grasp of problem `p` holds (`hold`, the hand
/// closed at `grasp`, opened to `pregrasp` to release it) after `lift`:
/// carried to a placement on `target` found by `search`, within `ptc`;
/// its trajectory sampled at `rate` (0: none).
PlaceOutcome planPlace(Problem& p, const PlaceTarget& target, PlaceSearch search, const Hold& hold,
                       const Eigen::VectorXd& pregrasp, const Eigen::VectorXd& grasp,
                       const LiftPath& lift, double rate,
                       const ob::PlannerTerminationCondition& ptc);

}  // namespace hfts::planner
