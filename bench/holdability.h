#pragma once
// Can the robot hold the object where it stands at all? hfts-bench's list
// of the cases (--holdable-only, --holdability).

#include <string>

#include "planner/plan_request.h"
#include "planner/planning_world.h"

namespace hfts::bench {

/// Whether the robot can hold the request's object where the request puts
/// it: the criterion of "an object the robot can hold"
/// (docs/robots.md#which-objects-a-robot-can-hold). It can when some leaf
/// grasp h is stable (Q(h) > 0), the thorough hand map puts the fingertips
/// within the plan's max_fingertip_error of its contacts (RMS), the hand
/// alone, with its palm where that posture puts it (a gripper: at any of
/// its palm_turns turns), is clear of the scene and the object at the
/// pre-grasp (full rule), along the closing motion and at the grasp
/// (fingertips may touch the object), and Phi(h) gives a collision-free
/// robot configuration for it with the fingertips within
/// max_fingertip_error: a goal the planner could return, only not
/// connected to the start. R(h)'s posture and then the hand's other
/// postures for the contacts are tried.
/// The leaves come from descents from the root to one level above the
/// leaves, alternately climbs of Eq. (1) (`iterations` per level, the
/// plan's objective and contact mask, grasps whose hand meets an obstacle
/// ranked last) and random walks (a hand may hold an object only by weaker
/// grasps), each through nodes no earlier descent passed; all leaves below
/// the node reached are tried, until one holds. A search: "not holdable" means none was found.
/// Decided before any descent: a target in collision, an object beyond the
/// fingertips' reach (robot::fingertipReach), no stable grasp possible.
struct Holdability {
  bool holdable = false;
  /// Why not, in words (empty when holdable).
  std::string reason;
  int climbs = 0;        ///< descents run (nodes whose leaves were all tried)
  int leaves = 0;        ///< leaves tried
  int stable = 0;        ///< of those, with Q(h) > 0
  int reached = 0;       ///< of those, with the fingertips on the contacts
  int hand_clear = 0;    ///< of those, with the hand alone clear of the scene
  double epsilon = 0.0;  ///< of the grasp that holds (0 when none)
};

/// Up to `climbs` descents (>= 1) for Holdability's criterion, with the
/// request's scene, object, placement, start (the whole-turn variants
/// kept are the ones nearest it, as in a plan), parameters (the robot's
/// defaults under them) and seed; the algorithm and time limit are unused.
/// The same request gives the same answer. Throws like planGrasp for a
/// malformed request and InvalidArgument ("climbs") for climbs < 1.
Holdability holdability(const planner::PlanningWorld& world, const planner::PlanRequest& request,
                        int climbs = 100);

}  // namespace hfts::bench
