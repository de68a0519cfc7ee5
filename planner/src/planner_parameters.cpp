#include "planner_parameters.h"

namespace hfts::planner {

GoalSamplingSettings goalSamplingSettings(const PlanSettings& s, const robot::RobotModel& robot) {
  GoalSamplingSettings g;
  g.coupled.weights.w_f = s.paper.w_f;
  g.coupled.weights.w_c = s.paper.w_c;
  g.coupled.weights.max_active = s.paper.n_a;
  g.coupled.samples = s.paper.kappa;
  g.coupled.min_iterations = s.paper.i_min;
  g.coupled.max_iterations = s.paper.i_max;
  g.decoupled_iterations = s.paper.decoupled_iterations;
  g.objective.alpha = s.paper.alpha;
  g.objective.friction = s.paper.friction;
  g.objective.cone_edges = s.paper.cone_edges;
  g.objective.torsional_friction = robot.torsionalFriction();
  g.objective.unstable_by_reach = s.heuristics.unstable_by_reach ? 1 : 0;
  g.objective.fit_check = s.heuristics.fit_check ? 1 : 0;
  g.objective.fit_clearance = s.heuristics.fit_clearance;
  g.max_fingertip_error = s.goal.max_fingertip_error;
  g.min_epsilon = s.goal.min_epsilon;
  g.max_penetration = s.goal.max_penetration;
  g.mask_contacts = s.heuristics.mask_contacts ? 1 : 0;
  g.other_postures = s.heuristics.other_postures ? 1 : 0;
  g.palm_turns = s.heuristics.palm_turns;
  return g;
}

}  // namespace hfts::planner
