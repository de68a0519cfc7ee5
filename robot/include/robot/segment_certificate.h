#pragma once
// Proving straight joint-space motions free (issue 45, docs/collision.md
// "Certified segments"): conservative advancement. At a state whose
// exact distance to everything is d, no point of the robot can reach
// anything before it has travelled d; MotionBound says how far along the
// motion that takes at the least, so the next state to look at lies that
// far on. A polyline (a path, or a trajectory's chords) is proven free
// with a clearance when the states reach its end, each farther than the
// clearance from everything the rule counts.

#include <Eigen/Core>

#include <cstddef>
#include <functional>
#include <vector>

#include "robot/collision_checker.h"
#include "robot/motion_bound.h"

namespace hfts::robot {

/// What a certified motion must keep its distance from, and how far
/// (docs/collision.md "Certified segments", "Near the grasp").
enum class CertifyRule {
  /// Every link keeps the clearance from the obstacles and the target,
  /// and from every link it may collide with (pairs not disabled), except
  /// that a link the motion does not move need only be free, and so need
  /// two links that do not move relative to each other along the motion,
  /// that are both the hand's (RobotModel::isHandLink) or that have at
  /// most kClearanceJointsApart moving joints between them: their
  /// distance is the robot's, not the motion's (an open hand's fingers, a
  /// wrist). Stricter than a scene's clearance rule (CollisionScene) only
  /// in the hand against the target, which the approach's last stretch
  /// (kApproach) lets come closer.
  kTransit,
  /// The approach to a pre-grasp (the motion ends there): as kTransit,
  /// but a hand link (RobotModel::isHandLink) may come closer than the
  /// clearance to the obstacles and the target over its last
  /// `approach_length` of travel before the end (as MotionBound bounds
  /// it): what it keeps shrinks in proportion from the clearance to 0,
  /// and it is free at the end.
  kApproach,
  /// The hand closing from the pre-grasp: hand links need only be free of
  /// everything, fingertip links may touch the target (their distance to
  /// the obstacles is proven, the depth they reach in the target is the
  /// grasp rule's to check at the grasp); every other link as kTransit.
  kClosing,
};

struct CertifyOptions {
  /// Distance (m) every link must keep, as the rule says, along the whole
  /// motion (>= 0).
  double clearance = 0.0;
  CertifyRule rule = CertifyRule::kTransit;
  /// kApproach: the travel (m) over which a hand link's clearance shrinks
  /// to 0 before the pre-grasp (> 0). MotionBound's travel overestimates a
  /// link's true path (by 1.5-3 times on the bundled arms), so the hand
  /// nears the object over a true path of a third to two thirds of this.
  double approach_length = 0.05;
  /// Distance queries allowed before the motion is given up (then not
  /// proven: a motion that grazes the clearance makes the steps shrink
  /// without end).
  std::size_t max_queries = 100000;
  /// Polled before every state; when it returns true the motion is given
  /// up as with max_queries (a planner's time limit).
  std::function<bool()> stop;
};

struct MotionCertificate {
  /// Proven: every point of the motion keeps what the rule asks.
  bool free = false;
  /// The smallest exact distance measured (m; FCL's, a link to the
  /// environment (the obstacles only, for a fingertip while closing) or
  /// link to link, whichever was measured there; not between two links
  /// that do not move relative to each other): the motion's smallest
  /// clearance is at most this, and at least what the rule asks when free.
  /// A mesh (the target, a mesh obstacle) is measured exactly only within
  /// the clearance plus 2 cm of its bounding box (farther, the box's
  /// distance proves as much): infinity when nothing exact came nearer.
  double clearance = 0.0;
  /// Where along the motion it was measured (k + t: the fraction t of the
  /// way from waypoint k to k + 1; a segment's runs from 0 to 1), and
  /// between what: a link and the obstacles or the target (other link -1),
  /// or two links.
  double at = 0.0;
  int nearest_link = -1;
  int nearest_other_link = -1;
  /// Other link -1: the distance was to the target (else to the obstacles).
  bool nearest_target = false;
  /// Not free: where the first distance within what the rule asks plus
  /// 0.1 mm was measured, or where the queries ran out (exhausted).
  double blocked_at = -1.0;
  /// Given up after options.max_queries queries, or when options.stop said so.
  bool exhausted = false;
  std::size_t queries = 0;       ///< distance queries made (environment or self)
  std::size_t self_queries = 0;  ///< of queries, those between two links
};

/// Certifies the polyline waypoints[0] -> waypoints[1] -> ... (straight
/// segments in joint space) against everything `checker` counts strictly
/// (obstacles, the target, the robot's own links), under options.rule. A
/// state counts as blocking when it is within the clearance asked plus
/// 0.1 mm (advancing towards a contact only approaches it), and FCL's
/// distances are trusted to 0.01 mm. Each distance proof (a link against
/// the environment, a link pair) carries over from one segment to the next.
/// Throws InvalidArgument ("clearance") for a negative or non-finite
/// clearance, ("approach_length") for one that is not > 0, ("path") for no waypoints, or waypoints
/// of the wrong size or not finite.
MotionCertificate certifyPath(CollisionChecker& checker, const MotionBound& bound,
                              const std::vector<Eigen::VectorXd>& waypoints,
                              const CertifyOptions& options = {});

/// certifyPath of the one segment a -> b ("segment" for bad ends).
MotionCertificate certifySegment(CollisionChecker& checker, const MotionBound& bound,
                                 const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                                 const CertifyOptions& options = {});

}  // namespace hfts::robot
