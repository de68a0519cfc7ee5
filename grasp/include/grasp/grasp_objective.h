#pragma once
// The HFTS grasp objective of the paper's Eq. (1), Q(h) / (R(h) + alpha):
// Ferrari-Canny quality over hand reachability, evaluated on a node's
// representative grasp and cached.

#include <cstddef>
#include <functional>
#include <vector>

#include "grasp/grasp_quality.h"
#include "grasp/hand_reachability.h"
#include "grasp/hfts_space.h"

namespace hfts::grasp {

struct ObjectiveOptions {
  double alpha = 1e-6;  ///< Eq. (1): keeps the ratio finite when R(h) = 0
  double friction = 0.5;
  int cone_edges = 8;
  /// Soft-finger torsional friction gamma (m), 0 for hard fingers: the
  /// robot's contact model (RobotModel::torsionalFriction).
  double torsional_friction = 0.0;
  /// 1: an unstable grasp (Q = 0) is valued -(R + alpha) instead of 0, so
  /// that among grasps without force closure the climb still moves towards
  /// those the hand reaches; every stable grasp stays above every unstable
  /// one. 0: Eq. (1) as in the paper (a flat 0 for all unstable grasps).
  /// For two-fingered hands most contact pairs are unstable and the
  /// reachable ones are the nearly antipodal ones; the planner turns it on
  /// for every hand (parameter "unstable_by_reach", kept on held-out
  /// evidence: docs/planning.md).
  int unstable_by_reach = 0;
  /// 1: Q(h) is 0 for contacts the hand cannot hold, whatever their
  /// friction cones say: two contacts farther apart than any two fingertips
  /// of the hand ever are (HandReachability::maxFingertipDistance: a
  /// gripper's stroke), or a contact whose inward normal points away from
  /// the other contacts (the pads of a grasp posture face each other,
  /// isGraspPosture; an expanding grasp inside a mug pushes them apart).
  /// A pair wider than that span is also valued as if R(h) were at least
  /// half the excess (each fingertip that far off its contact), so that
  /// among the grasps without force closure (unstable_by_reach) those the
  /// jaws can close on come first.
  /// 0: Q(h) of the contacts alone, as in the paper. On in objectiveOptions
  /// and the planner ("fit_check"): for a gripper R(h) of a pair beyond the
  /// stroke is only millimetres and of a reversed pair 2 lambda, so such
  /// pairs of high quality outranked the ones the jaws can hold.
  int fit_check = 0;
  /// With fit_check: the room (m) each fingertip needs beyond its contact
  /// to come in, so contacts farther apart than the hand's span less twice
  /// this do not fit either. A pair at the very stroke leaves the pre-grasp
  /// no opening: its pads sit on the surface and every approach grazes it
  /// ("fit_clearance"; the Panda's config sets 2.5 mm).
  double fit_clearance = 0.0;
};

/// The default options with the contact model of the robot's fingertips,
/// and fit_check.
ObjectiveOptions objectiveOptions(const robot::RobotModel& robot);

/// True when a hand whose fingertips are at most `span` (m) apart can hold
/// `contacts` (object frame, outward normals, one column per finger):
/// no two of them farther apart than `span`, and every inward normal with a
/// positive component towards the centroid of the other contacts.
bool handFits(const GraspContacts& contacts, double span);

/// How much farther apart (m) the two most distant contacts are than
/// `span`; 0 when they are within it.
double spanExcess(const GraspContacts& contacts, double span);

/// Q(h)'s request for `contacts` of the space's object: outward normals,
/// the object's centre of mass and rho, the options' friction, cone
/// edges and torsional friction.
GraspQualityRequest qualityRequest(const HftsSpace& space, const GraspContacts& contacts,
                                   const ObjectiveOptions& options);

/// One evaluated node.
struct GraspEvaluation {
  /// Q(h): Ferrari-Canny epsilon of the representative grasp (0 when
  /// ObjectiveOptions::fit_check finds that the hand cannot hold it).
  double quality = 0.0;
  double reachability = 0.0;  ///< R(h) (m) from the hand map
  /// Q / (R + alpha). With R = 0 the value is Q / alpha: an exactly
  /// reachable grasp outranks any inexact one of similar quality, and
  /// among exact ones quality decides.
  /// With ObjectiveOptions::unstable_by_reach, -(R + alpha) for Q = 0.
  double value = 0.0;
  /// With a hand check (GraspObjective::setHandCheck): the hand, placed as
  /// R(h)'s answer places it, meets an obstacle. Its value is then
  /// Q / (R + alpha + kBlockedHandPenalty): below every grasp of no better
  /// quality whose hand fits within centimetres.
  bool hand_blocked = false;
};

/// What a blocked hand adds to R(h) + alpha (m): far more than the
/// residual of a grasp the hand nearly reaches (millimetres to centimetres).
inline constexpr double kBlockedHandPenalty = 1.0;

/// True when the hand, answered for a grasp by R(h) (palm pose in the
/// object's frame, hand joints), meets an obstacle where the object stands.
using HandCheck = std::function<bool(const HandQuery&)>;

/// Evaluates HFTS nodes on their representative grasps and caches the
/// results (a node is evaluated once). Not thread-safe. The space and the
/// reachability must outlive it.
class GraspObjective {
 public:
  GraspObjective(const HftsSpace& space, const HandReachability& reachability,
                 ObjectiveOptions options = {});
  GraspEvaluation evaluate(const HftsNode& node);
  /// Environment-aware ranking (bench::holdability's search): every
  /// evaluation from now on also asks `check` (empty: none, Eq. (1) as in
  /// the paper). Forgets the cached evaluations.
  void setHandCheck(HandCheck check);
  const HftsSpace& space() const { return space_; }
  const ObjectiveOptions& options() const { return options_; }
  std::size_t evaluations() const { return size_; }

 private:
  struct Slot {
    HftsNode node;
    GraspEvaluation evaluation;
    bool used = false;
  };
  Slot& slotOf(const HftsNode& node);  // its slot, or the empty one it goes into
  void grow();

  const HftsSpace& space_;
  const HandReachability& reachability_;
  ObjectiveOptions options_;
  HandCheck handCheck_;
  // An open-addressing table (linear probing, at most half full): a run
  // caches up to ~140,000 evaluations, and a node-based map took 10-20 ms
  // to free them at the end of a plan, past its time limit.
  std::vector<Slot> slots_;
  std::size_t size_ = 0;
};

}  // namespace hfts::grasp
