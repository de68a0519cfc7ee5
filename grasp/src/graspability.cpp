#include "grasp/graspability.h"

#include <random>

#include "core/invalid_argument.h"
#include "grasp/grasp_objective.h"

namespace hfts::grasp {

Graspability graspability(const HftsSpace& space, const HandReachability& fast,
                          const HandReachability& thorough, const ObjectiveOptions& options,
                          std::size_t samples, double tolerance, std::uint64_t seed) {
  if (samples == 0) throw InvalidArgument("samples", "must be at least 1");
  if (!(tolerance >= 0.0)) throw InvalidArgument("tolerance", "must be >= 0");
  const GraspContacts leaves = space.leafContacts();
  Graspability out;
  if (leaves.positions.cols() == 0) return out;
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<Eigen::Index> pick(0, leaves.positions.cols() - 1);
  const Eigen::Matrix3Xd empty(3, space.fingers());
  GraspQualityRequest q = qualityRequest(space, {empty, empty}, options);
  for (std::size_t s = 0; s < samples; ++s) {
    for (int f = 0; f < space.fingers(); ++f) {
      const Eigen::Index leaf = pick(rng);
      q.positions.col(f) = leaves.positions.col(leaf);
      q.normals.col(f) = leaves.outward_normals.col(leaf);
    }
    ++out.sampled;
    if (!(graspQuality(q).epsilon > 0.0)) continue;
    ++out.stable;
    if (fast.query(q.positions, q.normals).residual <= tolerance ||
        thorough.query(q.positions, q.normals).residual <= tolerance)
      ++out.reachable;
  }
  return out;
}

}  // namespace hfts::grasp
