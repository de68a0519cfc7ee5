#pragma once
// How graspable an object is for a hand in free space: the fraction of its
// HFTS leaf grasps that are stable and that the hand can reach. Tells a
// user whether an object suits the hand before any scene is involved
// (hfts-preprocess --inspect, the service's objects.list).

#include <cstddef>
#include <cstdint>

#include "grasp/grasp_objective.h"
#include "grasp/hand_reachability.h"
#include "grasp/hfts_space.h"

namespace hfts::grasp {

struct Graspability {
  std::size_t sampled = 0;    ///< leaf grasps drawn
  std::size_t stable = 0;     ///< of those, with Q(h) > 0 (force closure)
  std::size_t reachable = 0;  ///< of the stable ones, with R(h) <= the tolerance

  /// reachable / sampled (0 when nothing was sampled).
  double fraction() const {
    return sampled == 0 ? 0.0 : static_cast<double>(reachable) / static_cast<double>(sampled);
  }
};

/// Draws `samples` leaf grasps of `space` uniformly (each finger's leaf
/// partition independently, seeded) and counts the stable ones (Q(h) > 0
/// with the objective's friction and cone edges) and, of those, the ones
/// the hand reaches: R(h) <= `tolerance` (m) by `fast`'s query, or when
/// that bound is above the tolerance, by `thorough`'s (the fast query's
/// R is an upper bound). Deterministic for the same arguments. Throws
/// InvalidArgument for samples = 0 or a negative tolerance.
Graspability graspability(const HftsSpace& space, const HandReachability& fast,
                          const HandReachability& thorough, const ObjectiveOptions& options = {},
                          std::size_t samples = 1000, double tolerance = 0.005,
                          std::uint64_t seed = 1);

}  // namespace hfts::grasp
