#pragma once
// The Python module's batch calls as plain C++ on contiguous arrays: many
// grasps' epsilon, many poses' arm IK, many configurations' collision
// checks in one call each. The module calls them with the GIL released;
// python/bench/batch_benchmark.cpp times the same functions without Python,
// so the difference is what the binding costs (docs/performance.md).

#include <cstddef>
#include <cstdint>
#include <vector>

#include "grasp/grasp_quality.h"
#include "robot/arm_ik.h"
#include "robot/collision_checker.h"

namespace hfts::python {

/// Epsilon of `grasps` grasps of `contacts` contacts each: `positions` and
/// `normals` hold grasp after grasp, contact after contact, x y z (grasps x
/// contacts x 3 doubles); every other field of the query comes from
/// `common` (its positions and normals are ignored). Writes `grasps` values
/// to `epsilons`. Throws InvalidArgument ("grasps[g].normals[i]", ...)
/// naming the first grasp the quality refuses and the contact's field.
void graspQualities(const double* positions, const double* normals, std::size_t grasps,
                    int contacts, const grasp::GraspQualityRequest& common, double* epsilons);

/// Every arm IK solution of many poses.
struct IkSolutions {
  std::vector<double> configurations;    ///< solution after solution, numArmDofs() values each
  std::vector<std::int64_t> pose_index;  ///< the pose each solution is of
};

/// The arm IK solutions of `count` poses (4 x 4 homogeneous matrices, row
/// after row, pose after pose) of the palm (`palm`) or the flange, in the
/// robot's base frame; pose i's numerical solver is seeded with `seed` + i
/// (a pose's solutions do not depend on the rest of the batch). Throws InvalidArgument ("poses[i]")
/// for a pose that is not finite or not rigid.
IkSolutions armIkBatch(const robot::ArmIk& ik, const double* poses, std::size_t count, bool palm,
                       std::uint64_t seed);

/// Whether each of `count` configurations (`dofs` values each, one after
/// the other) collides, as CollisionChecker::inCollision checks a batch.
/// Returns how many collide. Throws InvalidArgument ("configurations[i]")
/// for a configuration that is not finite or outside the joint limits.
std::size_t collisionBatch(robot::CollisionChecker& checker, const double* configurations,
                           std::size_t count, int dofs, const robot::CollisionRequest& request,
                           bool* colliding);

}  // namespace hfts::python
