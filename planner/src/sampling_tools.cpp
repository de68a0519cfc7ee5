#include "planner/sampling_tools.h"

#include <cmath>

namespace hfts::planner {

SamplingTools::SamplingTools(const PlanningWorld& world, const robot::Scene& scene,
                             const grasp::HftsSpace& hfts, robot::CollisionChecker& robotChecker,
                             const GoalSamplingSettings& settings)
    : space(hfts),
      checker(robotChecker),
      objective(hfts, world.handMap(), settings.objective),
      closer(world.surface(scene.target_object) == nullptr
                 ? nullptr
                 : std::make_unique<const grasp::HandCloser>(world.collisionModel(),
                                                             *world.surface(scene.target_object))),
      configurator(world.robot(), world.ik(), world.thoroughHandMap(), robotChecker,
                   scene.target_pose, scene.robot_base, closer.get()) {
  configurator.setTurns(settings.palm_turns);
  configurator.setMaxClosingError(settings.max_fingertip_error);
  if (settings.hand_clearance == 0) return;
  objective.setHandCheck([&robotChecker, object = scene.target_pose,
                          turns = settings.palm_turns](const grasp::HandQuery& hand) {
    // A hand that may turn about the contacts' line is blocked only when it
    // is at every one of palm_turns turns, evenly spaced from R(h)'s own.
    const int n = hand.free_turn ? turns : 1;
    for (int k = 0; k < n; ++k)
      if (!robotChecker.handInCollision(object * grasp::turnedPalm(hand, 2.0 * M_PI * k / n),
                                        hand.hand_configuration,
                                        robot::CollisionRequest::obstaclesOnly()))
        return false;
    return true;
  });
}

GoalSamplingContext SamplingTools::context(std::mt19937_64& rng,
                                           const GoalSamplingSettings& settings,
                                           const MotionCheck& closing) {
  return {&space,
          &objective,
          &configurator,
          &checker,
          &rng,
          closing,
          settings.max_fingertip_error,
          settings.min_epsilon,
          settings.other_postures != 0};
}

std::unique_ptr<GraspGoalSampler> SamplingTools::makeSampler(bool coupled, std::mt19937_64& rng,
                                                             const GoalSamplingSettings& settings,
                                                             const MotionCheck& closing) {
  const GoalSamplingContext c = context(rng, settings, closing);
  if (coupled) return std::make_unique<HftsGoalSampler>(c, settings.coupled);
  return std::make_unique<DecoupledGoalSampler>(c, settings.decoupled_iterations);
}

}  // namespace hfts::planner
