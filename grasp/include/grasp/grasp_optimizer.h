#pragma once
// Stochastic hill climbing on the HFTS (Sec. II-A) with the objective of
// Eq. (1) (grasp_objective.h), and the decoupled root-to-leaf optimiser.

#include <random>
#include <unordered_set>
#include <vector>

#include "grasp/grasp_objective.h"
#include "grasp/hfts_space.h"

namespace hfts::grasp {

/// The outcome of a hill climb on one level.
struct ClimbResult {
  HftsNode best;
  GraspEvaluation evaluation;
  /// The objective of the current node after each iteration: never
  /// decreases.
  std::vector<double> trace;
  bool found = false;  ///< false when every child was excluded
};

/// Stochastic hill climbing among the children of `parent` for
/// `iterations` steps: start at a random child, propose a neighbour that
/// differs in one finger's partition, move when it is better. Children in
/// `excluded` (e.g. sampled before) are never proposed.
ClimbResult hillClimb(GraspObjective& objective, const HftsNode& parent, int iterations,
                      std::mt19937_64& rng,
                      const std::unordered_set<HftsNode, HftsNodeHash>* excluded = nullptr);

/// The decoupled optimiser of Sec. II-A: hill climbing with a fixed number
/// of iterations on every level, descending into the best node, from the
/// root to a leaf. Returns the leaf.
ClimbResult optimizeToLeaf(GraspObjective& objective, int iterationsPerLevel, std::mt19937_64& rng);

}  // namespace hfts::grasp
