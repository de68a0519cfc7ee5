#pragma once
// What a plan returns (planGrasp, grasp_motion_planner.h): success or why
// not, the path, the grasp as executed, the trajectory, the statistics.

#include <Eigen/Geometry>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "grasp/hfts_space.h"
#include "physics/simulate_rest.h"
#include "planner/grasp_trajectory.h"
#include "planner/grasp_validation.h"
#include "planner/lift.h"
#include "planner/plan_statistics.h"

namespace hfts::planner {

enum class PlanFailure {
  kNone,
  kTimeLimit,
  kCancelled,
  kStartInCollision,
  kObjectInCollision,  ///< the target object intersects an obstacle
  kObjectUnreachable,  ///< beyond every fingertip's reach, or no sampled grasp had an arm IK
                       ///< solution
  kUnknownObject,
  /// The time ran out without one valid goal; the statistics' `rejected`
  /// counts say why the grasps tried were rejected.
  kNoValidGoal,
  /// No grasp can be stable with the contacts a fingertip can touch where
  /// the object stands (mask_contacts): decided before any search.
  kNoStableGraspClearOfSupport,
  /// Every motion goal is a joint goal, and every one of them collides.
  kGoalInCollision,
  /// The grasp found cannot be lifted (a search that does not check its
  /// goals' lifts: rrtconnect); the message says what blocks it.
  kLiftBlocked,
  /// The place goal's region allows the object no stable placement
  /// (placeFaces): decided before any search, the message says why.
  kNoStablePlacement,
  /// The object was grasped and lifted, but no placement on the region was
  /// reached (carried to, put down, released) within the time limit.
  kPlaceNotReached,
};

/// Snake-case name used in JSON and CSV ("time_limit", ...).
const char* toString(PlanFailure failure);

/// An HFTS node the coupled goal sampler cached (the paper's Fig. 5): its
/// representative contacts and how Eq. (1) rated it.
struct ExploredNode {
  int level = 0;
  Eigen::Matrix3Xd contacts_object;  ///< one column per finger, object frame
  double value = 0.0;                ///< Eq. (1): Q / (R + alpha)
  double quality = 0.0;              ///< epsilon of the representative grasp
  bool goal = false;                 ///< it gave a collision-free goal configuration
};

/// The grasp a plan ends in: the grasp as executed, the hand closed from
/// the pre-grasp until every fingertip pad touches the object.
struct PlannedGrasp {
  grasp::HftsNode node;
  /// Where the closed hand's fingertips touch the object's surface, one
  /// column per fingertip (robot order), and the mesh's normals there.
  Eigen::Matrix3Xd contacts_object;
  Eigen::Matrix3Xd contacts_world;
  Eigen::Matrix3Xd inward_normals_object;
  Eigen::Matrix3Xd inward_normals_world;
  /// Ferrari-Canny epsilon at those contacts (>= min_epsilon).
  double epsilon = 0.0;
  /// The HFTS node's representative contacts (object frame, one column
  /// per contact) and their epsilon: the grasp the search planned.
  Eigen::Matrix3Xd planned_contacts_object;
  double planned_epsilon = 0.0;
  double reachability = 0.0;  ///< R(h) (m)
  /// Largest distance of the planned hand posture's fingertips from the
  /// planned contacts (m; at most max_fingertip_error).
  double fingertip_error = 0.0;
  /// How deep the deepest fingertip link is inside the object at the
  /// grasp (m, >= 0, at most max_penetration); no other link touches it.
  double penetration = 0.0;
  Eigen::VectorXd hand_configuration;  ///< the closed hand
};

/// Placements the place search tried that gave no goal, by reason.
struct PlaceRejections {
  std::uint64_t unsupported = 0;  ///< it would overhang the top or leave the area
  std::uint64_t no_arm_ik = 0;    ///< no arm IK for the pre-place palm pose
  std::uint64_t colliding = 0;    ///< every pre-place configuration collides
  /// The straight descent onto the support, or the hand where it would
  /// put the object down (a finger under it), is not free.
  std::uint64_t descent_blocked = 0;
  std::uint64_t release_blocked = 0;  ///< the hand cannot open
  std::uint64_t retreat_blocked = 0;  ///< no straight retreat of the open hand is free
  std::uint64_t unstable = 0;         ///< released there, the object moves (rest check)

  std::uint64_t total() const {
    return unsupported + no_arm_ik + colliding + descent_blocked + release_blocked +
           retreat_blocked + unstable;
  }
};

/// Where a pick and place put the object and how (PlanRequest::place).
struct Placement {
  /// The object resting on the support (world; kRestingClearance above it).
  Eigen::Isometry3d object_pose = Eigen::Isometry3d::Identity();
  /// The face it rests on: its outward normal (object frame) and how far
  /// it must tilt before it tips (rad).
  Eigen::Vector3d face_normal = -Eigen::Vector3d::UnitZ();
  double tipping_angle = 0.0;
  /// The lift's end, ..., the pre-place: the palm `height` above where it
  /// puts the object down, the hand closed (each segment proven free or
  /// sampled with the object in the hand, as the path).
  std::vector<Eigen::VectorXd> carry;
  /// The pre-place, ..., the place: the palm straight down.
  std::vector<Eigen::VectorXd> descent;
  /// The place with the hand opened to the grasp's pre-grasp opening.
  Eigen::VectorXd open;
  /// The open hand, ..., the palm `height` away from the object on a
  /// straight line.
  std::vector<Eigen::VectorXd> retreat;
  /// "back" (against the approach axis), "up" or "up_back".
  std::string retreat_direction;
  /// The object released at object_pose (physics::simulateRest).
  physics::RestVerdict rest;
};

struct PlanResult {
  bool success = false;
  PlanFailure failure = PlanFailure::kNone;
  std::string message;  ///< human-readable reason when unsuccessful
  /// Start, ..., pre-grasp, grasp (the hand closed until its pads touch
  /// the object); a motion plan's: start, ..., goal (its last segment
  /// proven as a transit). With certify_path every segment is proven
  /// free (robot::certifyPath): the last under the closing rule (its
  /// fingertips' depth in the object sampled with the grasp rule at the
  /// final resolution), the one before under the approach rule, the
  /// others as transits. Without, every segment is sampled at the final
  /// resolution (the last with the grasp rule).
  std::vector<Eigen::VectorXd> path;
  /// With certify_path: the smallest distance (m) the proofs of the path
  /// from the start to the pre-grasp measured, between a link and the
  /// environment or two links that move relative to each other. The
  /// path's true smallest clearance lies between what the rule asked (0
  /// for now, issue 45) and this.
  std::optional<double> clearance;
  std::vector<std::string> joint_names;
  /// Where the object was: the request's object_pose, or the scene's
  /// target pose (resting on its support when the scene says so).
  Eigen::Isometry3d object_pose = Eigen::Isometry3d::Identity();
  /// A grasp plan's grasp (empty for a motion plan).
  PlannedGrasp grasp;
  /// With PlanRequest::lift: the lift from the grasp (path.back()), the
  /// object in the hand.
  std::optional<LiftPath> lift;
  /// With PlanRequest::place and success: where the object went and how.
  std::optional<Placement> place;
  /// With PlanRequest::place: the placements tried that gave no goal.
  PlaceRejections place_rejected;
  /// A motion plan's: the index of the request's goal the path ends at.
  std::optional<int> reached_goal;
  /// The path as a time-optimal trajectory (grasp_trajectory.h): empty
  /// points when not asked for, when the robot has no acceleration limits,
  /// or (never seen) when no collision-free one was found or it would hold
  /// more than kMaxTrajectorySamples states.
  GraspTrajectory trajectory;
  /// With PlanRequest::explored and the coupled planner: every node of the
  /// goal hierarchy cache but the root, in the order cached.
  std::vector<ExploredNode> explored;
  PlanStatistics stats;
  /// The seed of the search this result is from: the request's, or with
  /// racing (parameter `threads` > 1) the winning copy's. A request with
  /// this seed and one thread plans the same path again.
  std::uint64_t seed = 0;
  /// With PlanRequest::validate and success: the grasp checked again and
  /// simulated (its time is not in stats.planning_time).
  std::optional<Validation> validation;
};

}  // namespace hfts::planner
