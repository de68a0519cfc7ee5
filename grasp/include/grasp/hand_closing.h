#pragma once
// The grasp as the hand executes it: from the pre-grasp, the fingers close
// along their closing motion until each one touches the object's exact
// surface, as a hand does whose fingers stop at contact. The contacts it
// ends on, not the planned HFTS contacts, are the grasp's contacts.

#include <Eigen/Geometry>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "grasp/hfts_space.h"
#include "robot/collision_model.h"
#include "robot/kinematics.h"
#include "robot/object_surface.h"
#include "robot/robot_model.h"

namespace hfts::grasp {

struct ClosingOptions {
  /// A link within this distance (m) of the surface touches it: where the
  /// closing stops. Small against a pad's compliance, large against the
  /// signed distance's rounding.
  double contact_distance = 1e-4;
  /// A fingertip link touches with its pad when its pad normal and the
  /// surface's inward normal at the contact are at most this far apart
  /// (rad): 60 degrees, the side of a rounded pad that faces the object.
  double pad_cone = 1.0471975511965976;
  /// Steps of conservative advancement per finger before the closing is
  /// called stuck (a link sliding along the surface without touching it).
  int max_steps = 2000;
  /// Rounds of turning and moving the palm of a parallel gripper so that
  /// its jaws close flat and together on the object (HandCloser::close).
  int centering_rounds = 6;
};

/// Why a finger stopped.
enum class FingerStop {
  kPadContact,    ///< its fingertip pad touches the object
  kOtherContact,  ///< another part of the finger touched first
  kJointLimit,    ///< it reached its joint limit without touching
  kCoupled,       ///< a finger on the same DoF touched first (a gripper's other jaw)
  kStuck,         ///< max_steps without touching or reaching the limit
  kInside,        ///< a link of the finger is inside the object at the start (deeper than a touch)
};
const char* toString(FingerStop stop);

struct FingerClosure {
  FingerStop stop = FingerStop::kJointLimit;
  std::string link;  ///< the link that touched (kPadContact, kOtherContact)
  /// The surface point touched and the mesh's outward normal there (object
  /// frame; kPadContact and kOtherContact): within twice contact_distance
  /// of the link (a pad flat on a face: the point of the patch nearest the
  /// fingertip's own point; a jaw that stopped with its coupled partner:
  /// where it is, up to a contact distance short).
  Eigen::Vector3d contact = Eigen::Vector3d::Zero();
  Eigen::Vector3d outward_normal = Eigen::Vector3d::UnitZ();
  /// The closing motion's parameter where the finger stopped: 0 at the
  /// pre-grasp, 1 at the planned grasp, above 1 past it.
  double travel = 0.0;
};

/// The hand closed on the object.
struct HandClosure {
  /// The palm (object frame) the hand closed at: the requested one, or
  /// moved between two coupled jaws so that both touch (HandCloser::close).
  Eigen::Isometry3d palm = Eigen::Isometry3d::Identity();
  Eigen::VectorXd hand;                ///< closed posture (hand DoF)
  std::vector<FingerClosure> fingers;  ///< one per fingertip, in the robot's order

  /// Every fingertip touches the object with its pad.
  bool touches() const;
  /// The contacts (one column per fingertip, robot order; meaningful when
  /// touches()).
  GraspContacts contacts() const;
  /// Why not every pad touches, in words ("finger 'thumb': joint limit");
  /// empty when touches().
  std::string failure(const robot::RobotModel& model) const;
};

/// Closes a hand on an object (the robot of `model`, whose link spheres
/// bound how far a link is from the surface). The model and surface must outlive it;
/// close() only reads them (any thread).
class HandCloser {
 public:
  /// Throws InvalidArgument ("options") for a contact distance or pad cone
  /// that is not > 0, or max_steps < 1.
  HandCloser(const robot::CollisionModel& model, const robot::ObjectSurface& surface,
             ClosingOptions options = {});
  ~HandCloser();
  HandCloser(const HandCloser&) = delete;
  HandCloser& operator=(const HandCloser&) = delete;

  /// Closes the hand from `open` (hand DoF) along the straight line to
  /// `target` (the planned grasp), continued past it to the joint limits,
  /// with the palm at `palm` (object frame). Each finger stops where one of
  /// its links first touches the surface: found by conservative
  /// advancement (every step shorter than the distance to the surface
  /// divided by a bound on how fast any point of the finger moves), so no
  /// finger passes through a thin part. DoFs that do not move between open
  /// and target stay. A DoF that drives two fingertips moving against each
  /// other (a parallel-jaw gripper) stops when the first touches; as the
  /// jaws of a real gripper centre the object between them and square it
  /// against their pads, the palm is turned (up to 25 degrees) until the
  /// jaws lie flat on two nearly opposite faces and moved along the jaws'
  /// line until both touch together, and the result says where. Throws InvalidArgument ("hand") for
  /// postures of the wrong size or non-finite values.
  HandClosure close(const Eigen::Isometry3d& palm, const Eigen::VectorXd& open,
                    const Eigen::VectorXd& target) const;

 private:
  struct Finger;
  struct Touch;
  /// Closing travel used to tell which way a touching point moves.
  static constexpr double kProbeStep = 1e-4;
  /// Beyond this distance (m) a bound of a link's clearance does; nearer,
  /// it is computed exactly.
  static constexpr double kNear = 0.002;
  /// How far (m) a link that grazes the surface slides per step.
  static constexpr double kSlideStep = 5e-4;
  /// A touching point that moves within this angle (rad) of the surface's
  /// tangent plane grazes it (slides on); one that moves further into it
  /// pushes and stops the finger: 10 degrees.
  static constexpr double kGrazeAngle = 0.17453292519943295;

  std::vector<double> linkSpeeds(const Finger& finger, const Eigen::VectorXd& direction) const;
  /// A link's clearance (object frame pose): exact within kNear of the
  /// surface, else a lower bound above kNear without nearest points.
  robot::Clearance clearance(std::size_t link, const Eigen::Isometry3d& pose) const;
  /// Whether a link crossing the surface (object frame pose) reaches more
  /// than the contact distance into the object.
  bool startsDeep(const robot::Link& link, const Eigen::Isometry3d& pose) const;
  /// Whether the link's point nearest to the surface moves into it.
  bool pushesIn(const robot::Clearance& gap, const Eigen::Isometry3d& pose,
                const Eigen::Isometry3d& later) const;
  /// The centre of the patch where a pad (`pad`: its normal, object frame)
  /// lies flat on a face: the mean of the surface points that touch the
  /// link under a grid over the pad, when that touches it too.
  std::optional<robot::SurfacePoint> patchCentre(const Finger& finger, const robot::Link& link,
                                                 const Eigen::Isometry3d& pose,
                                                 const Eigen::Vector3d& pad) const;
  /// Fills `out` for the finger stopped by its link `i` (index into
  /// Finger::links): pad contact or another part, where.
  void stopAt(const Finger& finger, std::size_t i, const robot::LinkPoses& poses,
              const robot::Clearance& gap, Touch& out) const;
  Touch firstTouch(const Finger& finger, const Eigen::Isometry3d& palm, const Eigen::VectorXd& open,
                   const Eigen::VectorXd& direction, double limit) const;
  HandClosure closeAt(const Eigen::Isometry3d& palm, const Eigen::VectorXd& open,
                      const Eigen::VectorXd& direction, std::vector<Touch>& touches) const;
  /// A parallel gripper's palm turned so that its jaws close flat on the
  /// two faces they touch; the same palm when they do, or cannot.
  Eigen::Isometry3d squared(const HandClosure& closure, const std::vector<Touch>& touches,
                            const Eigen::VectorXd& open) const;
  /// A parallel gripper's palm moved along its jaws' line so that both
  /// touch together; the same palm when they do.
  Eigen::Isometry3d centred(const HandClosure& closure, const std::vector<Touch>& touches,
                            const Eigen::VectorXd& open, const Eigen::VectorXd& direction) const;

  const robot::RobotModel& model_;
  const robot::SphereModel& spheres_;
  const robot::ObjectSurface& surface_;
  ClosingOptions options_;
  std::vector<Finger> fingers_;
  /// The two fingers of a parallel gripper (one DoF drives both), if any.
  std::optional<std::pair<std::size_t, std::size_t>> jaws_;
};

}  // namespace hfts::grasp
