#pragma once
// Environment-aware grasp search: the contacts of a placed object that a
// fingertip cannot touch, because the support it stands on or another
// obstacle leaves no room for the finger there. HftsSpace never proposes a
// node that needs such a contact (hfts_space.h).

#include <Eigen/Geometry>

#include <vector>

#include "grasp/grasp_objective.h"
#include "grasp/hfts_space.h"
#include "hfts_db/object_database.h"
#include "robot/collision_checker.h"

namespace hfts::grasp {

/// How much the fingertip sphere is shrunk (m): a sphere that only grazes
/// the support (a contact at exactly the pad's radius above a table) keeps
/// its contact.
inline constexpr double kContactMaskClearance = 0.001;

/// One flag per database contact: true when a fingertip can touch it with
/// the object at `objectPose` (world frame). The pad of a finger touching
/// a contact holds a sphere of radius `padRadius` (robot::padRadius) whose
/// centre lies padRadius out along the contact's outward normal; where
/// that sphere, shrunk by `clearance`, meets an obstacle of `scene`, no finger fits. Throws
/// InvalidArgument for a pad radius that is not larger than the clearance.
std::vector<bool> fingertipReachableContacts(const db::ObjectDatabase& object,
                                             const Eigen::Isometry3d& objectPose,
                                             const robot::CollisionScene& scene, double padRadius,
                                             double clearance = kContactMaskClearance);

/// False when it is certain that no grasp of `space`, with any number of
/// fingers, is stable under the objective's friction and cone edges: the
/// contact wrenches of all its usable leaf contacts together (friction
/// cones circumscribing the true cones, so wider than Q(h)'s inscribed ones)
/// do not hold the origin (Wolfe's nearest point, exact up to rounding).
/// True does not promise a stable grasp of m fingers.
bool stableGraspPossible(const HftsSpace& space, const ObjectiveOptions& options);

}  // namespace hfts::grasp
