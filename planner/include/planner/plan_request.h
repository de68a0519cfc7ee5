#pragma once
// What a plan is asked for (planGrasp, grasp_motion_planner.h): the scene,
// the object and where it stands, the start, the algorithm, the seed, the
// time limit and the planner parameters by name.

#include <Eigen/Geometry>

#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "physics/simulate_grasp.h"
#include "robot/scene.h"

namespace hfts::planner {

enum class PlanAlgorithm {
  kCoupled,    ///< the paper's goal sampler (Algorithms 2-4)
  kDecoupled,  ///< the plain HFTS optimiser with a fixed number of iterations
  /// Outside baseline: OMPL's RRTConnect towards goals that the decoupled
  /// optimiser samples lazily in a second thread (lazy_goal_baseline.h).
  kRrtConnect,
};

/// Which defaults a request's parameters start from.
enum class PlannerPreset {
  /// The planner as measured best: the code's defaults, then the robot
  /// config's planner_defaults (docs/planning.md).
  kDefault,
  /// The paper's algorithm exactly (Algorithms 1-4 with Fig. 6's values):
  /// every addition beyond the paper off (paperSettings()), whatever the
  /// robot config says. The goal is still the grasp as executed (the hand
  /// closed until its pads touch, min_epsilon, max_penetration).
  kPaper,
};

/// The parameters kPaper sets, name and value: the switches and values
/// this project added to the paper's algorithm, each at the value that
/// turns it off.
const std::map<std::string, std::string>& paperSettings();

struct PlanRequest {
  robot::Scene scene;  ///< obstacles, robot base, target pose and start
  std::string object;  ///< object database name; empty: scene.target_object
  /// Overrides scene.target_pose and its rest_on (the object is put exactly here).
  std::optional<Eigen::Isometry3d> object_pose;
  std::optional<Eigen::VectorXd> start;  ///< overrides the scene's start
  PlanAlgorithm algorithm = PlanAlgorithm::kCoupled;
  /// The defaults `parameters` apply over.
  PlannerPreset preset = PlannerPreset::kDefault;
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

/// A declared planner parameter: name, default value and the range a value
/// must be in (OMPL's "low:step:high" notation; low and high are enforced,
/// the step is a hint).
struct PlannerParameterInfo {
  std::string name;
  std::string default_value;
  std::string range;
};

/// The seed of racing copy `copy` (0 .. threads - 1) of a request with
/// `seed`: copy 0 keeps the request's seed, the others get well-mixed
/// seeds derived from it (SplitMix64).
std::uint64_t racingSeed(std::uint64_t seed, int copy);

}  // namespace hfts::planner
