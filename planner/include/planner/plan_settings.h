#pragma once
// What a plan is set up with, typed (docs/planning.md#parameters): the
// paper's parameters (its Fig. 6), the search heuristics this project
// added beyond the paper, what a goal must pass, and how the search runs.
// Every field is also a named planner parameter (its name in quotes) that
// the service and hfts-bench set from text (setSetting). Where a value
// comes from is decided in one place, resolveSettings() (plan_request.h): the defaults
// below, then the robot's (its hand, its config's planner_defaults), the
// request's preset, then the request's own.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "planner/parameters.h"

namespace hfts::robot {
class RobotModel;
}

namespace hfts::planner {

/// A declared planner parameter: name, default value and the range a value
/// must be in (OMPL's "low:step:high" notation; low and high are enforced,
/// the step is a hint).
struct PlannerParameterInfo {
  std::string name;
  std::string default_value;
  std::string range;
};

/// The paper's parameters (Fig. 6; Sec. III-IV), at its values.
struct PaperParameters {
  double step_size = 0.1;    ///< "step_size": CBiRRT step (Eq. (3) metric)
  double p_max = 0.9;        ///< "p_max": goal probability p_g at most (Algorithm 1)
  double p_min = 0.01;       ///< "p_min": ... at least
  double p_w = 1.2;          ///< "p_w": how fast p_g falls with the live backward trees
  double p_goal_tree = 0.7;  ///< "p_goal_tree": share of backward steps on goal trees
  double d_m = 0.4;          ///< "d_m": projection distance D_m, m (Sec. III-A.2)
  double w_f = 0.5;          ///< "w_f": rating weight of non-connected free space (Eq. (4))
  double w_c = 4.0;          ///< "w_c": rating weight of connected free space (Eq. (4))
  int n_a = 20;              ///< "n_a": active children N_a
  int kappa = 4;             ///< "kappa": new samples per goal-sampling call
  int i_min = 20;            ///< "i_min": hill-climbing iterations, at least (<= i_max)
  int i_max = 100;           ///< "i_max": ... at most
  double alpha = 1e-6;       ///< "alpha": keeps Eq. (1)'s Q / (R + alpha) finite
  double friction = 0.5;     ///< "friction": mu of the grasp quality Q (design.md)
  int cone_edges = 8;        ///< "cone_edges": K of Q
  /// "weight_arm", "weight_hand": Eq. (3)'s omega of every arm (hand) DoF;
  /// unset: the robot config's dof_weights. Never 0.
  std::optional<double> weight_arm, weight_hand;
  /// "iterations": i per level of the decoupled baseline (Figs. 7-9) and
  /// of the RRTConnect baseline's sampler.
  int decoupled_iterations = 20;
};

/// The additions to Algorithms 1-4 (docs/planning.md, "The paper's
/// algorithm"); PlannerPreset::kPaper turns every one off.
struct SearchHeuristics {
  /// "p_local": share of backward extensions aimed within `local_radius`
  /// (rad, "local_radius") of one of the tree's own nodes; 0: none.
  double p_local = 1.0;
  double local_radius = 0.8;
  /// "other_postures": a stable leaf whose first hand posture gives no goal
  /// also tries the hand's other postures for the same contacts.
  bool other_postures = true;
  /// "palm_turns": turns about the contacts' line that Phi(h) tries for a
  /// hand that may turn so (a parallel gripper); 1: R(h)'s palm only.
  int palm_turns = 8;
  /// "mask_contacts": only contacts a fingertip can touch where the object
  /// stands make the HFTS.
  bool mask_contacts = true;
  /// "unstable_by_reach": an unstable grasp is valued -(R + alpha) instead
  /// of Eq. (1)'s flat 0.
  bool unstable_by_reach = true;
  /// "fit_check": Q = 0 for contacts the hand cannot span; with
  /// "fit_clearance" (m) of room each fingertip needs beyond its contact
  /// (a robot config may set it: the Panda's 2.5 mm).
  bool fit_check = true;
  double fit_clearance = 0.0;
};

/// What a goal must pass (docs/planning.md#what-a-goal-is).
struct GoalCriteria {
  /// "max_fingertip_error", m: which planned grasps are worth closing
  /// (a search-time filter).
  double max_fingertip_error = 0.005;
  /// "min_epsilon": Ferrari-Canny epsilon at the contacts the closed hand
  /// touches, at least.
  double min_epsilon = 0.002;
  /// "max_penetration", m: how deep a fingertip may be inside the object;
  /// every other link stays clear.
  double max_penetration = 0.001;
  /// "physics_check": a reached goal ends the search only when its grasp
  /// holds in physics.
  bool physics_check = true;
};

/// What a returned motion must be (docs/planning.md#certified-paths).
struct PathCriteria {
  /// "certify_path": every segment of the returned path, the goal's
  /// closing motion and the trajectory's chords proven free
  /// (robot::certifyPath); off: sampled at final_resolution. Off by
  /// default until the search keeps a margin: most shelf paths pass within
  /// 0.1 mm of something and are refused (docs/experiments/
  /// 2026-12-06-certified-paths.md).
  bool certify = false;
  /// "clearance", m: what every part of the path keeps from the obstacles,
  /// the target and the robot's own links, as the search checks it and as
  /// the final check (proof or samples) checks it, under the clearance
  /// rule (robot::CollisionScene; docs/planning.md#clearance): the hand
  /// need only be free of the target, and of everything while it closes.
  double clearance = 0.0;
};

/// How the search runs: none of these changes what a plan is.
struct ExecutionOptions {
  /// "threads": racing copies of the search, one thread each.
  int threads = 1;
  /// "sphere_tier": collision checks in two tiers (the same answers).
  bool sphere_tier = true;
  /// "collision_resolution": motion-check resolution of tree edges and
  /// smoothing (Eq. (3) metric).
  double collision_resolution = 0.02;
  /// "smoothing_steps": random shortcuts of the smoothing, at most (0: no
  /// smoothing; path_smoothing.h).
  int smoothing_steps = 200;
  /// "final_resolution": the returned path's dense re-check, and the
  /// resolution a goal's closing motion is checked at.
  double final_resolution = 0.0025;
};

struct PlanSettings {
  PaperParameters paper;
  SearchHeuristics heuristics;
  GoalCriteria goal;
  PathCriteria path;
  ExecutionOptions execution;
};

/// Which defaults a request's settings start from.
enum class PlannerPreset {
  /// The planner as measured best: the code's defaults, then the robot
  /// config's planner_defaults.
  kDefault,
  /// The paper's algorithm exactly (Algorithms 1-4 with Fig. 6's values):
  /// every addition beyond the paper off (paperSettings()), whatever the
  /// robot config says. The goal is still the grasp as executed (the hand
  /// closed until its pads touch, min_epsilon, max_penetration).
  kPaper,
};

/// The parameters kPaper sets, name and value: the additions this project
/// made to the paper's algorithm, each at the value that turns it off.
const std::map<std::string, std::string>& paperSettings();

/// The defaults for `robot`: the structs' own, then its config's
/// planner_defaults (robot::ModelError naming one that is unknown or out
/// of range); with kPaper, then paperSettings().
PlanSettings defaultSettings(const robot::RobotModel& robot,
                             PlannerPreset preset = PlannerPreset::kDefault);

/// Throws InvalidArgument ("parameters.<name>") for a field outside its
/// range (setSetting checks what it sets; typed settings are checked here)
/// and ("parameters.i_min") for i_min > i_max.
void checkSettings(const PlanSettings& settings);

/// The part of checkSettings that relates settings to each other: throws
/// InvalidArgument ("parameters.i_min") for i_min > i_max.
void checkSettingOrder(const PlanSettings& settings);

/// Sets the setting named `name` from text. Throws InvalidArgument
/// ("parameters.<name>") for an unknown name, text that is not a number
/// (or not an integer for an integer setting, 0 or 1 for a switch) or a
/// value outside its range.
void setSetting(PlanSettings& settings, const std::string& name, const std::string& value);

/// The range a named setting must be in. Throws InvalidArgument
/// ("parameters.<name>") for an unknown name.
ParameterRange settingRange(const std::string& name);

/// Every setting by name with its value in `settings` as text and its
/// range; an unset weight reads as the robot's first arm (last hand) DoF's.
std::vector<PlannerParameterInfo> describeSettings(const PlanSettings& settings,
                                                   const robot::RobotModel& robot);

}  // namespace hfts::planner
