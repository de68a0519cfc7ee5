#include "grasp/grasp_objective.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "core/invalid_argument.h"

namespace hfts::grasp {

ObjectiveOptions objectiveOptions(const robot::RobotModel& robot) {
  ObjectiveOptions options;
  options.torsional_friction = robot.torsionalFriction();
  options.fit_check = 1;
  return options;
}

double spanExcess(const GraspContacts& contacts, double span) {
  const Eigen::Matrix3Xd& p = contacts.positions;
  double widest = 0.0;
  for (Eigen::Index i = 0; i < p.cols(); ++i)
    for (Eigen::Index j = i + 1; j < p.cols(); ++j)
      widest = std::max(widest, (p.col(i) - p.col(j)).norm());
  return std::max(0.0, widest - span);
}

bool handFits(const GraspContacts& contacts, double span) {
  const Eigen::Matrix3Xd& p = contacts.positions;
  const Eigen::Index m = p.cols();
  const Eigen::Vector3d sum = p.rowwise().sum();
  for (Eigen::Index i = 0; i < m; ++i) {
    const Eigen::Vector3d others = (sum - p.col(i)) / static_cast<double>(m - 1);
    if (!(-contacts.outward_normals.col(i).dot(others - p.col(i)) > 0.0)) return false;
  }
  return spanExcess(contacts, span) == 0.0;
}

GraspQualityRequest qualityRequest(const HftsSpace& space, const GraspContacts& contacts,
                                   const ObjectiveOptions& options) {
  GraspQualityRequest q;
  q.positions = contacts.positions;
  q.normals = contacts.outward_normals;
  q.direction = NormalDirection::kOutward;
  q.center = space.database().geometry.center_of_mass;
  q.torque_scale = space.database().geometry.rho;
  q.friction = options.friction;
  q.cone_edges = options.cone_edges;
  q.torsional_friction = options.torsional_friction;
  return q;
}

GraspObjective::GraspObjective(const HftsSpace& space, const HandReachability& reachability,
                               ObjectiveOptions options)
    : space_(space), reachability_(reachability), options_(options) {
  if (!(options_.alpha > 0.0)) throw InvalidArgument("ObjectiveOptions::alpha", "must be > 0");
  if (!(options_.fit_clearance >= 0.0))
    throw InvalidArgument("ObjectiveOptions::fit_clearance", "must be >= 0");
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

void GraspObjective::setHandCheck(HandCheck check) {
  handCheck_ = std::move(check);
  slots_.clear();
  size_ = 0;
}

GraspEvaluation GraspObjective::evaluate(const HftsNode& node) {
  if (2 * (size_ + 1) > slots_.size()) grow();
  Slot& slot = slotOf(node);
  if (slot.used) return slot.evaluation;
  const GraspContacts grasp = space_.representative(node);
  GraspEvaluation e;
  const double span = reachability_.maxFingertipDistance() - 2.0 * options_.fit_clearance;
  if (options_.fit_check == 0 || handFits(grasp, span))
    e.quality = graspQuality(qualityRequest(space_, grasp, options_)).epsilon;
  const HandQuery hand = reachability_.query(grasp.positions, grasp.outward_normals);
  e.reachability = hand.residual;
  e.hand_blocked = handCheck_ && handCheck_(hand);
  // A pair wider than the usable span is reached no better than with each
  // fingertip half the excess off its contact, whatever R(h) (which knows the
  // full stroke) says: among grasps without force closure the climb then
  // prefers those the jaws can close on.
  const double reach = options_.fit_check == 0
                           ? e.reachability
                           : std::max(e.reachability, spanExcess(grasp, span) / 2);
  const double distance = reach + options_.alpha + (e.hand_blocked ? kBlockedHandPenalty : 0.0);
  e.value = e.quality / distance;  // Eq. (1)
  if (options_.unstable_by_reach != 0 && !(e.quality > 0.0)) e.value = -distance;
  slot = {node, e, true};
  ++size_;
  return e;
}

}  // namespace hfts::grasp
