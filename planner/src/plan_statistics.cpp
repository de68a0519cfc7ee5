#include "planner/plan_statistics.h"

namespace hfts::planner {

PlanStatistics planStatistics(const TreeStatistics& trees, const GoalSamplerStatistics& goals,
                              std::uint64_t objectiveEvaluations, std::uint64_t collisionChecks) {
  PlanStatistics s;
  s.iterations = trees.iterations;
  s.goal_sampling_calls = goals.calls;
  s.valid_goal_samples = goals.valid_goals;
  s.hfts_nodes_explored = goals.nodes_explored;
  s.objective_evaluations = objectiveEvaluations;
  s.goal_trees = trees.goal_trees;
  s.approximate_trees = trees.approximate_trees;
  s.merged_trees = trees.merged_trees;
  s.rejected_paths = trees.rejected_paths;
  s.dropped_goals = trees.dropped_goals;
  s.collision_checks = collisionChecks;
  s.forward_tree_size = trees.forward_tree_size;
  s.backward_tree_nodes = trees.backward_tree_nodes;
  s.path_length_raw = trees.path_length_raw;
  s.path_length_smoothed = trees.path_length_smoothed;
  s.final_check_time = trees.final_check_time;
  s.smoothing_time = trees.smoothing_time;
  s.certificate_queries = trees.certificate_queries + goals.certificate_queries;
  s.rejected = goals.rejected;
  return s;
}

}  // namespace hfts::planner
