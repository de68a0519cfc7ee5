#pragma once
// What a plan reports about its search: the trees of Algorithm 1 (or the
// baseline's), goal sampling, and the two together as PlanStatistics, the
// "stats" of a plan result (docs/protocol.md) and the columns of
// hfts-bench's CSV (docs/benchmarks.md).

#include <cstdint>

namespace hfts::planner {

/// How the trees grew.
struct TreeStatistics {
  std::uint64_t iterations = 0;  ///< of Algorithm 1's loop
  std::uint64_t goal_trees = 0;  ///< backward trees rooted at goals
  std::uint64_t approximate_trees = 0;
  std::uint64_t merged_trees = 0;    ///< approximate trees joined to T_f
  std::uint64_t rejected_paths = 0;  ///< paths that failed the dense re-check
  /// Reached goals whose grasp did not hold in physics (their trees dropped).
  std::uint64_t dropped_goals = 0;
  std::uint64_t projections = 0;  ///< backward steps bent by the heuristic
  std::uint64_t forward_tree_size = 0;
  std::uint64_t backward_tree_nodes = 0;  ///< in live backward trees
  double path_length_raw = 0.0;           ///< Eq. (3) metric, before smoothing
  double path_length_smoothed = 0.0;
  /// s: the final checks of found paths (proofs or dense samples), and
  /// the proofs' distance queries.
  double final_check_time = 0.0;
  std::uint64_t certificate_queries = 0;
  /// s: smoothing found paths and their final checks (final_check_time is
  /// part of it), the rejected ones too.
  double smoothing_time = 0.0;
};

/// Why leaf grasps that went through Phi(h) gave no goal, each counted
/// once, by the first reason in this order (the order Phi(h) decides them).
struct GraspRejections {
  std::uint64_t unstable = 0;   ///< epsilon = 0: no force closure
  std::uint64_t no_arm_ik = 0;  ///< no arm IK solution for the palm pose
  std::uint64_t out_of_hand_reach =
      0;                        ///< no fingertips within max_fingertip_error of the contacts
  std::uint64_t colliding = 0;  ///< every configuration reaching the contacts collides
  /// Closed from the pre-grasp, some finger does not end touching with its
  /// pad (joint limit, another part first).
  std::uint64_t no_pad_contact = 0;
  /// The contacts the closed hand touches have epsilon below min_epsilon.
  std::uint64_t weak_at_contacts = 0;
  std::uint64_t closing_blocked = 0;  ///< the closing motion (pre-grasp -> grasp) collides
  /// Reached, but no lift of the object is free (PlanRequest::lift).
  std::uint64_t lift_blocked = 0;

  std::uint64_t total() const {
    return unstable + no_arm_ik + out_of_hand_reach + colliding + no_pad_contact +
           weak_at_contacts + closing_blocked + lift_blocked;
  }
};

/// What a goal sampler did.
struct GoalSamplerStatistics {
  std::uint64_t calls = 0;        ///< GS
  std::uint64_t valid_goals = 0;  ///< VGS
  std::uint64_t approximate_goals = 0;
  /// GNS: distinct HFTS nodes the sampler settled on (the local optima of
  /// each level it searched), the paper's "explored" nodes of Fig. 5 and 8.
  std::uint64_t nodes_explored = 0;
  std::uint64_t configured_nodes = 0;     ///< nodes whose grasp went through Phi(h)
  std::uint64_t kinematic_solutions = 0;  ///< of those, nodes with at least one IK solution
  /// Of those, nodes whose Phi(h) tried palm turns (a hand with a free turn:
  /// every node but the unstable leaves).
  std::uint64_t turned_nodes = 0;
  GraspRejections rejected;  ///< leaf grasps without a goal, by reason
  /// Distance queries of the proofs of closing motions (certify_path).
  std::uint64_t certificate_queries = 0;
};

struct PlanStatistics {
  double planning_time = 0.0;  ///< s, wall clock of the whole request
  std::uint64_t iterations = 0;
  std::uint64_t goal_sampling_calls = 0;  ///< GS
  std::uint64_t valid_goal_samples = 0;   ///< VGS
  std::uint64_t hfts_nodes_explored = 0;  ///< GNS
  std::uint64_t objective_evaluations = 0;
  std::uint64_t goal_trees = 0;
  std::uint64_t approximate_trees = 0;
  std::uint64_t merged_trees = 0;
  /// Connections whose path failed the dense re-check (its goal tree dropped).
  std::uint64_t rejected_paths = 0;
  /// Goals reached whose grasp did not hold in physics (parameter
  /// physics_check; their goal trees dropped).
  std::uint64_t dropped_goals = 0;
  /// Goals whose grasp was simulated (physics_check): the dropped ones and
  /// the one that ended the search, if any.
  std::uint64_t physics_checks = 0;
  double physics_time = 0.0;  ///< s, wall clock spent in those simulations
  std::uint64_t collision_checks = 0;
  std::uint64_t forward_tree_size = 0;
  std::uint64_t backward_tree_nodes = 0;
  double path_length_raw = 0.0;  ///< Eq. (3) metric
  double path_length_smoothed = 0.0;
  /// s: the final checks of found paths, the rejected ones too (proven
  /// free with certify_path, else sampled at final_resolution).
  double final_check_time = 0.0;
  /// Distance queries of the proofs (paths, closing motions, trajectory).
  std::uint64_t certificate_queries = 0;
  /// s: the multi-tree planner's smoothing of found paths with their final
  /// checks (final_check_time is part of it); the rest of planning_time is
  /// set-up, search and the result (trajectory, physics).
  double smoothing_time = 0.0;
  /// s: a pick and place's place stage (the placement search and the
  /// carry's, its checks, its trajectory), part of planning_time.
  double place_time = 0.0;
  GraspRejections rejected;  ///< leaf grasps that gave no goal, by reason
};

/// The statistics of a finished search; planning_time is left to the
/// caller, who knows when the request began and ends.
PlanStatistics planStatistics(const TreeStatistics& trees, const GoalSamplerStatistics& goals,
                              std::uint64_t objectiveEvaluations, std::uint64_t collisionChecks);

/// Calls f(name, value) for each field of PlanStatistics, in declaration
/// order: the one list of the statistics' names (JSON members, CSV header).
template <typename F>
void forEachStatistic(const PlanStatistics& s, F&& f) {
  f("planning_time", s.planning_time);
  f("iterations", s.iterations);
  f("goal_sampling_calls", s.goal_sampling_calls);
  f("valid_goal_samples", s.valid_goal_samples);
  f("hfts_nodes_explored", s.hfts_nodes_explored);
  f("objective_evaluations", s.objective_evaluations);
  f("goal_trees", s.goal_trees);
  f("approximate_trees", s.approximate_trees);
  f("merged_trees", s.merged_trees);
  f("rejected_paths", s.rejected_paths);
  f("dropped_goals", s.dropped_goals);
  f("physics_checks", s.physics_checks);
  f("physics_time", s.physics_time);
  f("collision_checks", s.collision_checks);
  f("forward_tree_size", s.forward_tree_size);
  f("backward_tree_nodes", s.backward_tree_nodes);
  f("path_length_raw", s.path_length_raw);
  f("path_length_smoothed", s.path_length_smoothed);
  f("final_check_time", s.final_check_time);
  f("certificate_queries", s.certificate_queries);
  f("smoothing_time", s.smoothing_time);
  f("place_time", s.place_time);
  f("rejected_unstable", s.rejected.unstable);
  f("rejected_no_arm_ik", s.rejected.no_arm_ik);
  f("rejected_out_of_hand_reach", s.rejected.out_of_hand_reach);
  f("rejected_colliding", s.rejected.colliding);
  f("rejected_no_pad_contact", s.rejected.no_pad_contact);
  f("rejected_weak_at_contacts", s.rejected.weak_at_contacts);
  f("rejected_closing_blocked", s.rejected.closing_blocked);
  f("rejected_lift_blocked", s.rejected.lift_blocked);
}

}  // namespace hfts::planner
