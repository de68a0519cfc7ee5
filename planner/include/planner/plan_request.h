#pragma once
// What a plan is asked for (planGrasp, grasp_motion_planner.h): the scene,
// the object and where it stands (or motion-only goals), the start, the
// algorithm, the seed, the time limit and the planner's settings
// (plan_settings.h).

#include <Eigen/Geometry>

#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "physics/simulate_grasp.h"
#include "planner/lift.h"
#include "planner/motion_goal.h"
#include "planner/place_goal.h"
#include "planner/plan_settings.h"
#include "robot/scene.h"

namespace hfts::planner {

enum class PlanAlgorithm {
  kCoupled,    ///< the paper's goal sampler (Algorithms 2-4)
  kDecoupled,  ///< the plain HFTS optimiser with a fixed number of iterations
  /// Outside baseline: OMPL's RRTConnect towards goals that the decoupled
  /// optimiser samples lazily in a second thread (lazy_goal_baseline.h).
  kRrtConnect,
};

enum class PlaceSearch {
  /// The placements as a hierarchy (resting face, region cells, yaw)
  /// searched by the paper's goal sampler, C_free proximity guiding it.
  kCoupled,
  /// A stable placement drawn at random first, then planned to.
  kDecoupled,
};

struct PlanRequest {
  robot::Scene scene;  ///< obstacles, robot base, target pose and start
  std::string object;  ///< object database name; empty: scene.target_object
  /// Overrides scene.target_pose and its rest_on (the object is put exactly here).
  std::optional<Eigen::Isometry3d> object_pose;
  std::optional<Eigen::VectorXd> start;  ///< overrides the scene's start
  /// Motion-only goals (motion_goal.h): when not empty, the plan is a
  /// path from the start to whichever goal the multi-tree planner reaches
  /// first, with no grasp; the object (`object`, else the scene's target,
  /// when either names one) is then an obstacle like the others.
  std::vector<MotionGoal> goals;
  PlanAlgorithm algorithm = PlanAlgorithm::kCoupled;
  /// The settings, typed; unset: defaultSettings(robot, preset). Start
  /// from defaultSettings() to change a few (resolveSettings says the order).
  std::optional<PlanSettings> settings;
  /// The defaults when `settings` is unset.
  PlannerPreset preset = PlannerPreset::kDefault;
  std::optional<int> iterations;  ///< decoupled, rrtconnect: i per level (default 20)
  std::uint64_t seed = 1;
  /// s, counted from the call; the search stops at searchTimeLimit() of
  /// it (60 s: Fig. 6 of the paper).
  double time_limit = 60.0;
  /// Any planner parameter by name over the settings (see
  /// plannerParameters()), value as text, e.g. {"p_max", "0.8"}: how the
  /// service and hfts-bench set them.
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
  /// After the grasp, lift the object clear of its support, checked with
  /// the object in the hand (lift.h, docs/placement.md): a goal whose lift
  /// is blocked is refused. nullopt: the plan ends with the hand closed
  /// (motion plans never lift).
  std::optional<LiftOptions> lift = LiftOptions{};
  /// Pick and place (docs/placement.md): after the lift, carry the object
  /// to a stable placement on the goal's region, put it down, open the
  /// hand and retreat, all in one plan (PlanResult::place). Needs a lift;
  /// the descent and the retreat are as long as it.
  std::optional<PlaceGoal> place;
  /// How the placement is searched.
  PlaceSearch place_search = PlaceSearch::kCoupled;
};

inline constexpr double kMaxTrajectoryRate = 1000.0;

/// A request's settings, the one place that knows their order: its typed
/// `settings` when given, else defaultSettings(robot, its preset); then its
/// `parameters` by name; then its top-level `iterations`. Typed settings
/// are checked whole (checkSettings), each value by name as it is set, and
/// the result's order last (checkSettingOrder). Throws InvalidArgument ("parameters.<name>",
/// "iterations") for an unknown name or a value outside its range, and
/// ("parameters.i_min") for i_min > i_max.
PlanSettings resolveSettings(const robot::RobotModel& robot, const PlanRequest& request);

/// The seed of racing copy `copy` (0 .. threads - 1) of a request with
/// `seed`: copy 0 keeps the request's seed, the others get well-mixed
/// seeds derived from it (SplitMix64).
std::uint64_t racingSeed(std::uint64_t seed, int copy);

/// The part of a request's `time_limit` the search may use: the rest (5 %
/// of the limit, at most 0.3 s) is left for the work that follows a found
/// plan and cannot be cut short (validating its grasp, its trajectory).
double searchTimeLimit(double time_limit);

}  // namespace hfts::planner
