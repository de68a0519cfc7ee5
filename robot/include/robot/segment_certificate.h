#pragma once
// Proving a straight joint-space segment free (issue 45, docs/collision.md
// "Certified segments"): conservative advancement. At a state whose
// exact distance to everything is d, no point of the robot can reach
// anything before it has travelled d; MotionBound says how far along the
// segment that takes at the least, so the next state to look at lies that
// far on. The segment is proven free with a clearance when the states
// reach its end, each farther than the clearance from everything.

#include <Eigen/Core>

#include <cstddef>

#include "robot/collision_checker.h"
#include "robot/motion_bound.h"

namespace hfts::robot {

struct CertifyOptions {
  /// Distance (m) every link must keep from the obstacles, the target and
  /// the links it may collide with, along the whole segment (>= 0).
  double clearance = 0.0;
  /// Distance queries allowed for one segment before it is given up (then
  /// not proven: a segment that grazes the clearance makes the steps
  /// shrink without end).
  std::size_t max_queries = 100000;
};

struct SegmentCertificate {
  /// Proven: every point of the segment keeps options.clearance from
  /// everything.
  bool free = false;
  /// The smallest exact distance measured (m; FCL's, robot to environment
  /// or link to link, whichever was measured there): the segment's
  /// smallest clearance is at most this, and at least options.clearance
  /// when free.
  double clearance = 0.0;
  /// Where along the segment (0 at a, 1 at b) it was measured, and
  /// between what: a link and the environment (other link -1), or two links.
  double at = 0.0;
  int nearest_link = -1;
  int nearest_other_link = -1;
  /// Not free: where the first distance within options.clearance plus
  /// 0.1 mm was measured, or where the queries ran out (exhausted).
  double blocked_at = -1.0;
  bool exhausted = false;        ///< given up after options.max_queries queries
  std::size_t queries = 0;       ///< distance queries made (environment or self)
  std::size_t self_queries = 0;  ///< of queries, those between two links
};

/// Certifies the straight segment a -> b against everything `checker`
/// counts strictly (obstacles, the target, the robot's own links). A
/// state counts as blocking when it is within the clearance plus 0.1 mm
/// (advancing towards a contact only approaches it), and FCL's distances
/// are trusted to 0.01 mm.
/// Throws InvalidArgument ("clearance") for a negative or non-finite
/// clearance, ("segment") for ends of the wrong size or not finite.
SegmentCertificate certifySegment(CollisionChecker& checker, const MotionBound& bound,
                                  const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                                  const CertifyOptions& options = {});

}  // namespace hfts::robot
