#include "grasp/grasp_optimizer.h"

#include <algorithm>
#include <stdexcept>

namespace hfts::grasp {

namespace {

/// A random child of `parent` that differs from `from` in one finger.
HftsNode neighbour(const HftsSpace& space, const HftsNode& parent, const HftsNode& from,
                   std::mt19937_64& rng) {
  HftsNode out = from;
  const int finger = std::uniform_int_distribution<int>(0, space.fingers() - 1)(rng);
  // Re-draw that finger's partition among its siblings via a random child.
  const std::uint64_t n = space.numChildren(parent);
  const HftsNode random =
      space.child(parent, std::uniform_int_distribution<std::uint64_t>(0, n - 1)(rng));
  out.parts[static_cast<std::size_t>(finger)] = random.parts[static_cast<std::size_t>(finger)];
  return out;
}

}  // namespace

ClimbResult hillClimb(GraspObjective& objective, const HftsNode& parent, int iterations,
                      std::mt19937_64& rng,
                      const std::unordered_set<HftsNode, HftsNodeHash>* excluded) {
  const HftsSpace& space = objective.space();
  const std::uint64_t n = space.numChildren(parent);
  if (n == 0) throw std::invalid_argument("hillClimb: the parent is a leaf");
  auto allowed = [&](const HftsNode& node) {
    return excluded == nullptr || !excluded->count(node);
  };
  ClimbResult result;
  std::uniform_int_distribution<std::uint64_t> any(0, n - 1);
  // Start at a random allowed child (a bounded number of draws, then a scan).
  for (int attempt = 0; attempt < 64 && !result.found; ++attempt) {
    result.best = space.child(parent, any(rng));
    result.found = allowed(result.best);
  }
  for (std::uint64_t i = 0; i < n && !result.found; ++i) {
    result.best = space.child(parent, i);
    result.found = allowed(result.best);
  }
  if (!result.found) return result;
  result.evaluation = objective.evaluate(result.best);
  for (int it = 0; it < iterations; ++it) {
    const HftsNode candidate = neighbour(space, parent, result.best, rng);
    if (allowed(candidate) && !(candidate == result.best)) {
      const GraspEvaluation e = objective.evaluate(candidate);
      if (e.value > result.evaluation.value) {
        result.best = candidate;
        result.evaluation = e;
      }
    }
    result.trace.push_back(result.evaluation.value);
  }
  return result;
}

ClimbResult optimizeToLeaf(GraspObjective& objective, int iterationsPerLevel,
                           std::mt19937_64& rng) {
  if (iterationsPerLevel < 0) throw std::invalid_argument("iterations must be >= 0");
  HftsNode node = objective.space().root();
  ClimbResult result;
  while (!objective.space().isLeaf(node)) {
    result = hillClimb(objective, node, iterationsPerLevel, rng);
    node = result.best;
  }
  return result;
}

}  // namespace hfts::grasp
