#pragma once
// Motion planning for the robot holding the object (docs/placement.md),
// internal to the planner library: the multi-tree planner in the world of
// the robot holding it (carryWorld), used by the carry to a placement and
// by the lift when no straight line lifts the object.

#include <ompl/base/PlannerTerminationCondition.h>

#include <memory>
#include <optional>
#include <vector>

#include "plan_problem.h"
#include "planner/lift.h"

namespace hfts::planner {

/// Algorithm 1's planner (problem `p`'s settings and seed) for the robot
/// holding the object as `hold` says, its hand fixed as it closed at
/// `grasp`, among the scene's obstacles (the target is in the hand),
/// keeping `clearance` (m) from them; segments proven with `certify_path`.
class CarryPlanning {
 public:
  CarryPlanning(const Problem& p, const Hold& hold, const Eigen::VectorXd& grasp, double clearance);

  /// The path from `start` to a goal `sampler` hands out (its last state),
  /// within `ptc`; none when not found.
  std::optional<std::vector<Eigen::VectorXd>> solve(const Eigen::VectorXd& start,
                                                    GoalSampler& sampler,
                                                    const ob::PlannerTerminationCondition& ptc);

  const PlanningWorld& world() const { return *world_; }
  robot::CollisionChecker& checker() { return checker_; }
  MultiTreeCBiRRT& planner() { return *planner_; }

 private:
  const std::shared_ptr<const PlanningWorld> world_;
  PlanSettings settings_;
  robot::CollisionChecker checker_;
  ob::SpaceInformationPtr si_;
  std::shared_ptr<MultiTreeCBiRRT> planner_;
};

/// The scene's obstacles: its target and what the target rests on named
/// no more (the object is in the hand).
robot::Scene obstaclesOf(const robot::Scene& scene);

/// How long a planned lift may search (s) within the plan's time limit.
inline constexpr double kPlannedLiftTime = 1.0;

/// The lift of problem `p`'s grasp when no straight line lifts it: a path
/// of the robot holding the object (`hold`, the hand as it closed at
/// `grasp`) planned to a palm pose `height` or more above the grasp's,
/// straight above it or up to 0.3 m aside (towards the robot's base, back
/// against the approach, or along the world's x and y), its orientation
/// within 20 degrees of the grasp's; no clearance kept (the object starts
/// 1 mm above its support, as for the straight lift). Interpolated so that
/// no joint moves more than 0.01 rad between waypoints; direction
/// "planned". None within kPlannedLiftTime or `ptc`.
std::optional<LiftPath> plannedLift(const Problem& p, const Hold& hold,
                                    const Eigen::VectorXd& grasp, double height,
                                    const ob::PlannerTerminationCondition& ptc);

}  // namespace hfts::planner
