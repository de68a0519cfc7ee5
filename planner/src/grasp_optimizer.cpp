#include "planner/grasp_optimizer.h"

#include <algorithm>
#include <stdexcept>

namespace hfts::planner {

GraspObjective::GraspObjective(const HftsSpace& space, const HandReachability& reachability,
                               ObjectiveOptions options)
    : space_(space), reachability_(reachability), options_(options) {
  if (!(options_.alpha > 0.0)) throw std::invalid_argument("objective: alpha must be > 0");
}

GraspObjective::Slot& GraspObjective::slotOf(const HftsNode& node) {
  const std::size_t mask = slots_.size() - 1;  // the size is a power of two
  const std::size_t home = HftsNodeHash{}(node)&mask;
  for (std::size_t i = home;; i = (i + 1) & mask)
    if (!slots_[i].used || slots_[i].node == node) return slots_[i];
}

void GraspObjective::grow() {
  std::vector<Slot> old(std::max<std::size_t>(1024, 2 * slots_.size()));
  old.swap(slots_);
  for (const Slot& s : old)
    if (s.used) slotOf(s.node) = s;
}

GraspEvaluation GraspObjective::evaluate(const HftsNode& node) {
  if (2 * (size_ + 1) > slots_.size()) grow();
  Slot& slot = slotOf(node);
  if (slot.used) return slot.evaluation;
  const GraspContacts grasp = space_.representative(node);
  GraspEvaluation e;
  GraspQualityRequest q;
  q.positions = grasp.positions;
  q.normals = grasp.outward_normals;
  q.direction = NormalDirection::kOutward;
  q.center = space_.database().geometry.center_of_mass;
  q.torque_scale = space_.database().geometry.rho;
  q.friction = options_.friction;
  q.cone_edges = options_.cone_edges;
  e.quality = graspQuality(q).epsilon;
  e.reachability = reachability_.query(grasp.positions, grasp.outward_normals).residual;
  e.value = e.quality / (e.reachability + options_.alpha);  // Eq. (1)
  slot = {node, e, true};
  ++size_;
  return e;
}

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

}  // namespace hfts::planner
