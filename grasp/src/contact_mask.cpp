#include "grasp/contact_mask.h"

#include <cmath>
#include <string>

#include "core/invalid_argument.h"
#include "grasp/grasp_quality.h"
#include "min_norm_point.h"

namespace hfts::grasp {

std::vector<bool> fingertipReachableContacts(const db::ObjectDatabase& object,
                                             const Eigen::Isometry3d& objectPose,
                                             const robot::CollisionScene& scene, double padRadius,
                                             double clearance) {
  if (!(padRadius > clearance) || !std::isfinite(padRadius))
    throw InvalidArgument("padRadius", "must be larger than the clearance (" +
                                           std::to_string(clearance) + " m), got " +
                                           std::to_string(padRadius));
  std::vector<bool> reachable(object.numContacts());
  for (std::size_t i = 0; i < reachable.size(); ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    const Eigen::Vector3d contact = objectPose * object.positions.row(row).transpose();
    const Eigen::Vector3d normal = objectPose.linear() * object.normals.row(row).transpose();
    reachable[i] =
        !scene.sphereTouchesObstacles(contact + padRadius * normal, padRadius - clearance);
  }
  return reachable;
}

bool stableGraspPossible(const HftsSpace& space, const ObjectiveOptions& options) {
  const GraspContacts contacts = space.leafContacts();
  if (contacts.positions.cols() == 0) return false;
  GraspQualityRequest q = qualityRequest(space, contacts, options);
  // The K-gon around the true cone: every force of Q(h)'s inscribed cones,
  // whatever their tangents, lies in these.
  q.friction = options.friction / std::cos(M_PI / options.cone_edges);
  return distanceToHull(contactWrenches(q)) == 0.0;
}

}  // namespace hfts::grasp
