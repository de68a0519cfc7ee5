#pragma once
// Grasp-and-motion planning as one call: PlanRequest -> PlanResult. Builds
// the collision checker, the HFTS goal sampler (or the decoupled baseline)
// and the multi-tree CBiRRT for a request and runs them. OMPL stays behind
// this header (see multi_tree_cbirrt.h for the planner itself).

#include <Eigen/Geometry>

#include <atomic>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "grasp/hfts_space.h"
#include "planner/grasp_trajectory.h"
#include "planner/grasp_validation.h"
#include "planner/plan_statistics.h"
#include "planner/planning_world.h"
#include "robot/scene.h"

namespace hfts::planner {

enum class PlanAlgorithm {
  kCoupled,    ///< the paper's goal sampler (Algorithms 2-4)
  kDecoupled,  ///< the plain HFTS optimiser with a fixed number of iterations
  /// Outside baseline: OMPL's RRTConnect towards goals that the decoupled
  /// optimiser samples lazily in a second thread (lazy_goal_baseline.h).
  kRrtConnect,
};

struct PlanRequest {
  robot::Scene scene;  ///< obstacles, robot base, target pose and start
  std::string object;  ///< object database name; empty: scene.target_object
  /// Overrides scene.target_pose and its rest_on (the object is put exactly here).
  std::optional<Eigen::Isometry3d> object_pose;
  std::optional<Eigen::VectorXd> start;  ///< overrides the scene's start
  PlanAlgorithm algorithm = PlanAlgorithm::kCoupled;
  std::optional<int> iterations;  ///< decoupled, rrtconnect: i per level (default 20)
  std::uint64_t seed = 1;
  /// s, counted from the call; feeds the search's termination condition
  /// (60 s: Fig. 6 of the paper).
  double time_limit = 60.0;
  /// Any declared planner parameter by name (see plannerParameters()),
  /// value as text, e.g. {"p_max", "0.8"}.
  std::map<std::string, std::string> parameters;
  /// Samples per second of the result's trajectory, 0 .. kMaxTrajectoryRate;
  /// 0: none (nor when the robot config has no max_accelerations).
  double trajectory_rate = 100.0;
  /// Record the HFTS nodes the coupled goal sampler visited (PlanResult::explored).
  bool explored = false;
  /// Check a plan's grasp again and simulate it (grasp_validation.h):
  /// PlanResult::validation. Takes a few seconds of physics.
  bool validate = false;
  /// The physics check's options (with `validate`).
  physics::SimulationOptions simulation;
};

inline constexpr double kMaxTrajectoryRate = 1000.0;

enum class PlanFailure {
  kNone,
  kTimeLimit,
  kCancelled,
  kStartInCollision,
  kObjectInCollision,  ///< the target object intersects an obstacle
  kObjectUnreachable,  ///< no sampled grasp had an arm IK solution
  kUnknownObject,
  /// The time ran out without one valid goal; the statistics' `rejected`
  /// counts say why the grasps tried were rejected.
  kNoValidGoal,
  /// No grasp can be stable with the contacts a fingertip can touch where
  /// the object stands (mask_contacts): decided before any search.
  kNoStableGraspClearOfSupport,
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

struct PlanResult {
  bool success = false;
  PlanFailure failure = PlanFailure::kNone;
  std::string message;  ///< human-readable reason when unsuccessful
  /// Start, ..., pre-grasp, grasp (the hand closed until its pads touch
  /// the object): the last segment was checked with the grasp rule, all
  /// others with the full rule at the planner's final resolution.
  std::vector<Eigen::VectorXd> path;
  std::vector<std::string> joint_names;
  /// Where the object was: the request's object_pose, or the scene's
  /// target pose (resting on its support when the scene says so).
  Eigen::Isometry3d object_pose = Eigen::Isometry3d::Identity();
  PlannedGrasp grasp;
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

/// A declared planner parameter: name, default value and the range a value
/// must be in (OMPL's "low:step:high" notation; low and high are enforced,
/// the step is a hint).
struct PlannerParameterInfo {
  std::string name;
  std::string default_value;
  std::string range;
};
std::vector<PlannerParameterInfo> plannerParameters(const PlanningWorld& world);

/// The seed of racing copy `copy` (0 .. threads - 1) of a request with
/// `seed`: copy 0 keeps the request's seed, the others get well-mixed
/// seeds derived from it (SplitMix64).
std::uint64_t racingSeed(std::uint64_t seed, int copy);

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
/// plan's objective and contact mask, hand_clearance ranking) and random
/// walks (a hand may hold an object only by weaker grasps), each through
/// nodes no earlier descent passed; all leaves below the node reached are
/// tried, until one holds. A search: "not holdable" means none was found.
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
Holdability holdability(const PlanningWorld& world, const PlanRequest& request, int climbs = 100);

/// A successful plan as an animated binary glTF (robot/plan_export.h):
/// the request's scene, the object where it was planned, the robot moving
/// along the result's trajectory, the contacts and the path. Throws
/// InvalidArgument ("trajectory") when the result has no trajectory.
std::string planGlb(const PlanningWorld& world, const PlanRequest& request,
                    const PlanResult& result);

/// Plans a grasp and a path to it. Single-threaded (kRrtConnect: two
/// threads, both joined before it returns); the same request and seed give
/// the same result unless the time limit cuts it short (kRrtConnect: see
/// LazyGoalRrtConnect::solve).
/// With the parameter `threads` = N > 1, N copies of the search race in N
/// threads, copy i with racingSeed(seed, i); the first to find a plan
/// wins, the others are stopped, and the result is the winner's (its seed
/// in PlanResult::seed). When none finds a plan the result is copy 0's
/// failure. Which copy wins depends on timing: racing trades the
/// determinism of one thread for the time to the first plan.
/// `cancel` (may be null) stops it from another thread. Throws
/// InvalidArgument naming the field ("start", "time_limit", "iterations",
/// "parameters.<name>") for a malformed request: a start of the wrong size,
/// not finite or outside the joint limits, a negative or non-finite time
/// limit, an unknown parameter or a value outside its range.
PlanResult planGrasp(const PlanningWorld& world, const PlanRequest& request,
                     const std::atomic<bool>* cancel = nullptr);

/// A successful plan's grasp checked again and simulated
/// (grasp_validation.h) with the request's planner parameters
/// (min_epsilon, max_penetration, final_resolution, friction) and
/// simulation options: what PlanRequest::validate adds to a result.
/// Throws InvalidArgument ("plan") for a plan without a grasp.
Validation validatePlan(const PlanningWorld& world, const PlanRequest& request,
                        const PlanResult& plan);

}  // namespace hfts::planner
