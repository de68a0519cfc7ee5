#include "planner_parameters.h"

#include <ompl/util/Console.h>

#include "planner/configuration_space.h"
#include "robot/collision_checker.h"

namespace hfts::planner {

void quietOmpl() {
  static const bool once = [] {
    ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
    return true;
  }();
  (void)once;
}

const std::map<std::string, std::string>& paperSettings() {
  // Every addition to Algorithms 1-4 (docs/planning.md, "Beyond the
  // paper"), at its value that turns it off.
  static const std::map<std::string, std::string> settings = {
      {"retreat", "0"},            // Algorithm 1: no palm retreat from backward roots
      {"p_local", "0"},            // Algorithm 1: uniform samples only
      {"stable_nodes", "0"},       // Algorithm 2: unstable inner nodes are added
      {"other_postures", "0"},     // Phi(h): R(h)'s posture only
      {"hand_clearance", "0"},     // Eq. (1) alone
      {"palm_turns", "1"},         // Phi(h): R(h)'s own palm only
      {"mask_contacts", "0"},      // every contact in the HFTS
      {"unstable_by_reach", "0"},  // Eq. (1)'s flat 0 for unstable grasps
      {"fit_check", "0"},          // Q(h) from the friction cones alone
      {"fit_clearance", "0"},
      {"physics_check", "0"},  // Algorithm 1: a reached goal ends the search
  };
  return settings;
}

std::vector<PlannerParameterInfo> plannerParameterInfo(const robot::RobotModel& robot) {
  quietOmpl();
  robot::CollisionChecker checker(robot, robot::Scene{}, nullptr);
  const PlanParameters parameters(makeSpaceInformation(robot, checker, kTreeResolution), robot);
  std::vector<PlannerParameterInfo> out;
  for (const auto& [name, param] : parameters.all.getParams())
    out.push_back({name, param->getValue(), param->getRangeSuggestion()});
  return out;
}

}  // namespace hfts::planner
