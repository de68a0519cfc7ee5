#include "planner/sampling_tools.h"

namespace hfts::planner {

SamplingTools::SamplingTools(const PlanningWorld& world, const robot::Scene& scene,
                             const grasp::HftsSpace& hfts, robot::CollisionChecker& robotChecker,
                             const GoalSamplingSettings& settings)
    : space(hfts),
      checker(robotChecker),
      objective(hfts, world.handMap(), settings.objective),
      configurator(world.robot(), world.ik(), world.thoroughHandMap(), robotChecker,
                   scene.target_pose, scene.robot_base) {
  configurator.setTurns(settings.palm_turns);
  if (settings.hand_clearance == 0) return;
  objective.setHandCheck([&robotChecker, object = scene.target_pose](const grasp::HandQuery& hand) {
    return robotChecker.handTouchesObstacles(object * hand.palm_pose, hand.hand_configuration);
  });
}

GoalSamplingContext SamplingTools::context(std::mt19937_64& rng,
                                           const GoalSamplingSettings& settings,
                                           double approachResolution) {
  return {&space,
          &objective,
          &configurator,
          &checker,
          &rng,
          approachResolution,
          settings.max_fingertip_error,
          settings.other_postures != 0};
}

std::unique_ptr<GraspGoalSampler> SamplingTools::makeSampler(bool coupled, std::mt19937_64& rng,
                                                             const GoalSamplingSettings& settings,
                                                             double approachResolution) {
  const GoalSamplingContext c = context(rng, settings, approachResolution);
  if (coupled) return std::make_unique<HftsGoalSampler>(c, settings.coupled);
  return std::make_unique<DecoupledGoalSampler>(c, settings.decoupled_iterations);
}

}  // namespace hfts::planner
