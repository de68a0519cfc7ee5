#pragma once
// From a grasp to robot configurations: the paper's Phi(h).

#include <Eigen/Geometry>

#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "grasp/hand_closing.h"
#include "grasp/hand_reachability.h"
#include "grasp/hfts_space.h"
#include "robot/arm_ik.h"
#include "robot/collision_checker.h"

namespace hfts::grasp {

enum class ConfigurationLabel { kCollisionFree, kColliding, kNoKinematicSolution };

const char* toString(ConfigurationLabel label);

/// The pre-grasp opening of a hand posture (hand DoF only): every DoF that
/// drives one joint, or several fingers all along their pad normals, moved
/// by the robot's pregrasp_offset away from the pads, within its limits.
Eigen::VectorXd openedHand(const robot::RobotModel& model, const Eigen::VectorXd& hand);

/// One robot configuration for a grasp.
struct GraspConfiguration {
  ConfigurationLabel label = ConfigurationLabel::kNoKinematicSolution;
  /// The pre-grasp: the planned grasp with every single-finger hand DoF
  /// opened by the robot's pregrasp_offset, in the direction that moves its
  /// fingertip away from the pad normal (shared DoF such as the SDH knuckle
  /// keep their value). Checked with the full collision rule: this is the
  /// planner's goal configuration. Empty without IK solution.
  Eigen::VectorXd pregrasp;
  /// With `closure`: the grasp as executed, the hand closed from the
  /// pre-grasp until its fingers touch (checked with the grasp rule).
  /// Without: the planned hand posture, not checked (a configuration that
  /// only rates a grasp; the pre-grasp decides its label).
  Eigen::VectorXd grasp;
  /// How the hand closed (configure() with `close`; shared by every arm
  /// solution of one palm pose), else null.
  std::shared_ptr<const HandClosure> closure;
  robot::CollisionPair collision;  ///< what collides (kColliding only)
  /// Largest distance from a fingertip of the planned hand posture to its
  /// contact (m): how well R(h) reaches the HFTS contacts.
  double fingertip_error = 0.0;
  /// Index, in the same list, of an earlier configuration with the same
  /// hand whose arm differs from this one's by whole turns of its joints
  /// only (robot::differByWholeTurns): every link is where that one's is,
  /// so its label, collision and fingertip error are copied, not
  /// recomputed. -1: none (this one was checked).
  int same_poses_as = -1;
};

/// All configurations of a grasp in a scene.
struct GraspConfigurations {
  HandQuery hand;  ///< hand posture, palm pose (object frame) and R(h)
  std::vector<GraspConfiguration>
      configurations;  ///< one per IK solution, or one kNoKinematicSolution
  /// Palm turns about the line through the contacts that were tried (a
  /// hand with HandQuery::free_turn; 1 otherwise) and how many of them the
  /// hand alone could not take for an obstacle.
  int turns_tried = 1;
  int turns_blocked = 0;
};

/// Computes Phi(h): hand posture and palm pose from the hand reachability
/// map (the thorough query: its local refinement puts the fingertips onto
/// the contacts), every arm IK solution for that palm pose, the pre-grasp
/// opening, and the collision checks. The references must outlive it.
class GraspConfigurator {
 public:
  /// `objectPose`: object frame in the world; `robotBase`: base link in the
  /// world (both from the scene). `closer` (may be null: configure() then
  /// never closes the hand) closes the hand on this object.
  GraspConfigurator(const robot::RobotModel& model, const robot::ArmIk& ik,
                    const HandReachability& hand, robot::CollisionChecker& checker,
                    const Eigen::Isometry3d& objectPose, const Eigen::Isometry3d& robotBase,
                    const HandCloser* closer = nullptr);

  /// For the contacts of a grasp (object frame, outward normals, one column
  /// per finger). `turn` false: R(h)'s own palm pose only, also for a hand
  /// that may turn (setTurns), e.g. for a grasp that cannot be a goal.
  /// `close` (with a closer): the hand closes from the pre-grasp until its
  /// fingers touch (HandCloser::close, once per palm pose, before the arm
  /// IK: a gripper's palm may move to centre its jaws), and the executed
  /// grasp is checked with the grasp rule; else only the pre-grasp is
  /// checked.
  GraspConfigurations configure(const GraspContacts& grasp, std::mt19937_64& rng, bool turn = true,
                                bool close = false);

  /// For an HFTS node: its representative grasp (inner nodes too: the goal
  /// sampler asks for configurations of approximate grasps).
  GraspConfigurations configure(const HftsSpace& space, const HftsNode& node, std::mt19937_64& rng,
                                bool turn = true, bool close = false);

  /// For the contacts of a grasp with a given hand answer for them (e.g.
  /// one of HandReachability::queryAlternatives): every arm IK solution,
  /// labelled, at the answer's palm pose (a hand with a free turn and
  /// `turn`: at the turns of setTurns).
  GraspConfigurations configure(const GraspContacts& grasp, HandQuery hand, std::mt19937_64& rng,
                                bool turn = true, bool close = false);

  /// The grasp's configurations with other hand postures than configure()
  /// uses (HandReachability::queryAlternatives with fingertips within
  /// `maxPositionError` m RMS of the contacts), one entry per posture,
  /// closed as configure() closes them.
  std::vector<GraspConfigurations> configureOtherHands(const GraspContacts& grasp,
                                                       double maxPositionError,
                                                       std::mt19937_64& rng, bool close = false);
  /// The same, given the answer configure() used (`used`, the hand of its
  /// result): saves the repeated HandReachability::query.
  std::vector<GraspConfigurations> configureOtherHands(const GraspContacts& grasp,
                                                       const HandQuery& used,
                                                       double maxPositionError,
                                                       std::mt19937_64& rng, bool close = false);

  /// grasp::openedHand for this robot.
  Eigen::VectorXd openedHand(const Eigen::VectorXd& hand) const;

  /// How many palm turns about the line through the contacts Phi(h) tries
  /// for a hand that may turn about it (HandQuery::free_turn: a parallel
  /// jaw gripper), evenly spaced from a random start, in that order, until
  /// one gives a collision-free configuration. A turn whose hand alone
  /// meets an obstacle gets no arm IK. 1 (the default): only the palm pose
  /// of R(h)'s answer. Throws InvalidArgument naming "turns" below 1.
  void setTurns(int turns);
  int turns() const { return turns_; }

  /// Keeps, of the whole-turn variants of each arm IK branch
  /// (robot::differByWholeTurns: every link in the same place), only the
  /// one nearest `arm` (numArmDofs() values) joint by joint, which is also
  /// the nearest in the planner's weighted joint metric. The planner passes
  /// its start, where its trees grow from; a variant a full turn away from
  /// it only lengthens the path to the same grasp. Without a reference (the
  /// default) every variant is a configuration of its own, labelled once
  /// per branch. Throws InvalidArgument naming "arm" for another size or
  /// non-finite values.
  void setArmReference(const Eigen::VectorXd& arm);

  /// configure() closes the hand only for grasps whose planned fingertips
  /// are within `error` m of their contacts (the planner's
  /// max_fingertip_error: no other grasp can be a goal); default: all.
  /// Throws InvalidArgument ("max_fingertip_error") unless error > 0.
  void setMaxClosingError(double error);

 private:
  /// Appends every arm IK solution for the palm at `palm` (object frame),
  /// labelled; with `close`, closed (see configure()).
  void appendArmConfigurations(const GraspContacts& grasp, const HandQuery& hand,
                               const Eigen::Isometry3d& palm, bool close, std::mt19937_64& rng,
                               std::vector<GraspConfiguration>& out);
  /// With an arm reference: moves every solution to the whole-turn variant
  /// of its branch nearest the reference (in the joint limits) and drops
  /// the duplicates; a solution that already was that variant keeps its
  /// place in the list.
  void keepNearestTurns(std::vector<Eigen::VectorXd>& arms) const;
  /// Appends the arm IK solutions for `palm` with the hand at `graspHand`
  /// (pre-grasp: `opened`), labelled: the pre-grasp under the full rule,
  /// with a closure also the grasp under the grasp rule.
  void appendArms(const Eigen::Isometry3d& palm, const Eigen::VectorXd& graspHand,
                  const Eigen::VectorXd& opened, std::shared_ptr<const HandClosure> closure,
                  std::mt19937_64& rng, std::vector<GraspConfiguration>& out);
  /// Largest distance from a fingertip of the hand's planned posture, its
  /// palm at `palm` (object frame), to the contact it takes.
  double fingertipError(const GraspContacts& grasp, const HandQuery& hand,
                        const Eigen::Isometry3d& palm) const;
  /// configure() for a hand with a free turn and turns_ > 1.
  void configureTurns(const GraspContacts& grasp, bool close, GraspConfigurations& out,
                      std::mt19937_64& rng);

  const robot::RobotModel& model_;
  const robot::ArmIk& ik_;
  const HandReachability& hand_;
  robot::CollisionChecker& checker_;
  const HandCloser* closer_;
  Eigen::Isometry3d objectInBase_;
  Eigen::Isometry3d objectInWorld_;
  int turns_ = 1;
  Eigen::VectorXd reference_;  // empty: every whole-turn variant
  double maxClosingError_ = std::numeric_limits<double>::infinity();
};

}  // namespace hfts::grasp
