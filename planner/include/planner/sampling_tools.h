#pragma once
// What one thread samples goals with in one plan. The planning thread of
// planGrasp and the RRTConnect baseline's sampling thread each build their
// own: the collision checker's FCL objects move on every query and the
// objective caches, so no two threads may share them.

#include <memory>
#include <random>

#include "grasp/grasp_configurations.h"
#include "grasp/grasp_objective.h"
#include "grasp/hfts_space.h"
#include "planner/goal_sampler.h"
#include "planner/planning_world.h"
#include "robot/collision_checker.h"
#include "robot/scene.h"

namespace hfts::planner {

/// The Eq. (1) objective and Phi(h) on one thread's collision checker.
struct SamplingTools {
  /// `world`, `scene`, `space` and `checker` must outlive the tools;
  /// `scene` holds the target's pose and name. The objective is set up from
  /// `settings` (its options; hand_clearance, which bench::holdability
  /// sets: for a hand with a free turn blocked only when blocked at each of
  /// palm_turns turns), Phi(h) with its palm_turns.
  SamplingTools(const PlanningWorld& world, const robot::Scene& scene,
                const grasp::HftsSpace& space, robot::CollisionChecker& checker,
                const GoalSamplingSettings& settings);

  /// What a goal sampler on these tools works with: random decisions from
  /// `rng`, closing motions checked as `closing` says, the fingertip
  /// tolerance of `settings`.
  GoalSamplingContext context(std::mt19937_64& rng, const GoalSamplingSettings& settings,
                              const MotionCheck& closing);

  /// The coupled sampler (Algorithm 2) or the decoupled one, set up from
  /// `settings`, drawing from `rng`. Throws InvalidArgument ("parameters.*")
  /// for inconsistent settings.
  std::unique_ptr<GraspGoalSampler> makeSampler(bool coupled, std::mt19937_64& rng,
                                                const GoalSamplingSettings& settings,
                                                const MotionCheck& closing);

  const grasp::HftsSpace& space;
  robot::CollisionChecker& checker;
  grasp::GraspObjective objective;
  /// Closes the hand on the target (null when the world has no surface
  /// for it: no grasp is then a goal).
  std::unique_ptr<const grasp::HandCloser> closer;
  grasp::GraspConfigurator configurator;
};

}  // namespace hfts::planner
