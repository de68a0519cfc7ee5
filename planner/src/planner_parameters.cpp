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
