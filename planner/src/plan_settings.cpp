// The planner's settings by name (plan_settings.h): one table of every
// parameter's name, range and field, as an OMPL ParamSet over a
// PlanSettings (parameters.h checks the ranges); the robot's defaults.
#include "planner/plan_settings.h"

#include <ompl/base/GenericParam.h>

#include <map>
#include <string>

#include "core/invalid_argument.h"
#include "robot/robot_model.h"

namespace hfts::planner {
namespace {

namespace ob = ompl::base;

/// A 0/1 parameter over a bool field.
void declareSwitch(ob::ParamSet& p, const std::string& name, bool& field) {
  declareParameter<int>(
      p, name, {0, 1, 1}, [&field](int v) { field = v != 0; }, [&field] { return field ? 1 : 0; });
}

/// A weight that reads 0 while unset (describeSettings shows the robot's).
void declareWeight(ob::ParamSet& p, const std::string& name, std::optional<double>& field) {
  declareParameter<double>(
      p, name, {0.001, 0.05, 100.0}, [&field](double w) { field = w; },
      [&field] { return field.value_or(0.0); });
}

/// The table: every setting's name, range and field. Ranges as
/// docs/planning.md lists them; Fig. 6 of the paper gives the paper's
/// defaults (the structs').
void declareSettings(ob::ParamSet& p, PlanSettings& s) {
  PaperParameters& a = s.paper;
  declareParameter(p, "step_size", {0.001, 0.01, 10.0}, a.step_size);
  declareParameter(p, "p_max", {0.0, 0.05, 1.0}, a.p_max);
  declareParameter(p, "p_min", {0.0, 0.01, 1.0}, a.p_min);
  declareParameter(p, "p_w", {0.0, 0.1, 100.0}, a.p_w);
  declareParameter(p, "p_goal_tree", {0.0, 0.05, 1.0}, a.p_goal_tree);
  declareParameter(p, "d_m", {0.0, 0.05, 10.0}, a.d_m);
  declareParameter(p, "w_f", {1e-6, 0.1, 1000.0}, a.w_f);
  declareParameter(p, "w_c", {1e-6, 0.1, 1000.0}, a.w_c);
  declareParameter(p, "n_a", {1, 1, 100000}, a.n_a);
  declareParameter(p, "kappa", {1, 1, 1000}, a.kappa);
  declareParameter(p, "i_min", {0, 1, 100000}, a.i_min);
  declareParameter(p, "i_max", {0, 1, 100000}, a.i_max);
  declareParameter(p, "alpha", {1e-12, 1e-6, 1.0}, a.alpha);
  declareParameter(p, "friction", {0.001, 0.05, 10.0}, a.friction);
  declareParameter(p, "cone_edges", {3, 1, 64}, a.cone_edges);
  declareWeight(p, "weight_arm", a.weight_arm);
  declareWeight(p, "weight_hand", a.weight_hand);
  declareParameter(p, "iterations", {1, 1, 100000}, a.decoupled_iterations);

  SearchHeuristics& h = s.heuristics;
  declareParameter(p, "p_local", {0.0, 0.05, 1.0}, h.p_local);
  declareParameter(p, "local_radius", {0.01, 0.05, 3.2}, h.local_radius);
  declareSwitch(p, "other_postures", h.other_postures);
  declareParameter(p, "palm_turns", {1, 1, 64}, h.palm_turns);
  declareSwitch(p, "mask_contacts", h.mask_contacts);
  declareSwitch(p, "unstable_by_reach", h.unstable_by_reach);
  declareSwitch(p, "fit_check", h.fit_check);
  declareParameter(p, "fit_clearance", {0.0, 0.0005, 0.05}, h.fit_clearance);

  GoalCriteria& g = s.goal;
  declareParameter(p, "max_fingertip_error", {1e-9, 0.001, 0.1}, g.max_fingertip_error);
  declareParameter(p, "min_epsilon", {0.0, 0.001, 1.0}, g.min_epsilon);
  declareParameter(p, "max_penetration", {0.0, 0.0005, 0.01}, g.max_penetration);
  declareSwitch(p, "physics_check", g.physics_check);

  declareSwitch(p, "certify_path", s.path.certify);
  declareParameter(p, "clearance", {0.0, 0.001, 0.1}, s.path.clearance);

  ExecutionOptions& e = s.execution;
  declareParameter(p, "threads", {1, 1, 32}, e.threads);
  declareSwitch(p, "sphere_tier", e.sphere_tier);
  declareParameter(p, "collision_resolution", {1e-4, 1e-4, 1.0}, e.collision_resolution);
  declareParameter(p, "smoothing_steps", {0, 10, 100000}, e.smoothing_steps);
  declareParameter(p, "final_resolution", {1e-4, 1e-4, 1.0}, e.final_resolution);
}

}  // namespace

void checkSettings(const PlanSettings& settings) {
  // Each value set again, on a copy: setParameter checks it.
  PlanSettings s = settings;
  ob::ParamSet p;
  declareSettings(p, s);
  for (const auto& [name, param] : p.getParams()) {
    const bool unsetWeight = (name == "weight_arm" && !s.paper.weight_arm) ||
                             (name == "weight_hand" && !s.paper.weight_hand);
    if (!unsetWeight) setParameter(p, name, param->getValue());
  }
  checkSettingOrder(s);
}

void checkSettingOrder(const PlanSettings& s) {
  if (s.paper.i_max < s.paper.i_min)
    throw InvalidArgument("parameters.i_min",
                          "must be <= i_max, got i_min = " + std::to_string(s.paper.i_min) +
                              " > i_max = " + std::to_string(s.paper.i_max));
}

const std::map<std::string, std::string>& paperSettings() {
  // Every addition to Algorithms 1-4 (docs/planning.md, "The paper's
  // algorithm"), at its value that turns it off.
  static const std::map<std::string, std::string> settings = {
      {"p_local", "0"},            // Algorithm 1: uniform samples only
      {"other_postures", "0"},     // Phi(h): R(h)'s posture only
      {"palm_turns", "1"},         // Phi(h): R(h)'s own palm only
      {"mask_contacts", "0"},      // every contact in the HFTS
      {"unstable_by_reach", "0"},  // Eq. (1)'s flat 0 for unstable grasps
      {"fit_check", "0"},          // Q(h) from the friction cones alone
      {"fit_clearance", "0"},
      {"physics_check", "0"},  // Algorithm 1: a reached goal ends the search
  };
  return settings;
}

void setSetting(PlanSettings& settings, const std::string& name, const std::string& value) {
  ob::ParamSet p;
  declareSettings(p, settings);
  setParameter(p, name, value);
}

ParameterRange settingRange(const std::string& name) {
  // The table of ranges once per process: every planner a plan builds asks
  // for a dozen of them (declaring all settings took 90 us a planner).
  static const std::map<std::string, ParameterRange> ranges = [] {
    PlanSettings s;
    ob::ParamSet p;
    declareSettings(p, s);
    std::map<std::string, ParameterRange> out;
    for (const auto& [setting, param] : p.getParams())
      out[setting] = ParameterRange::fromSuggestion(param->getRangeSuggestion());
    return out;
  }();
  const auto it = ranges.find(name);
  if (it == ranges.end()) throw InvalidArgument("parameters." + name, "unknown planner parameter");
  return it->second;
}

PlanSettings defaultSettings(const robot::RobotModel& robot, PlannerPreset preset) {
  PlanSettings s;
  for (const auto& [name, value] : robot.plannerDefaults()) {
    try {
      setSetting(s, name, value);
    } catch (const InvalidArgument& e) {
      throw robot::ModelError("robot config '" + robot.name() + "': planner_defaults." + name +
                              ": " + e.problem());
    }
  }
  if (preset == PlannerPreset::kPaper)
    for (const auto& [name, value] : paperSettings()) setSetting(s, name, value);
  return s;
}

std::vector<PlannerParameterInfo> describeSettings(const PlanSettings& settings,
                                                   const robot::RobotModel& robot) {
  PlanSettings s = settings;
  const Eigen::VectorXd& weights = robot.dofWeights();
  if (!s.paper.weight_arm && weights.size() > 0) s.paper.weight_arm = weights(0);
  if (!s.paper.weight_hand && weights.size() > 0) s.paper.weight_hand = weights(weights.size() - 1);
  ob::ParamSet p;
  declareSettings(p, s);
  std::vector<PlannerParameterInfo> out;
  for (const auto& [name, param] : p.getParams())
    out.push_back({name, param->getValue(), param->getRangeSuggestion()});
  return out;
}

}  // namespace hfts::planner
