// planner::resolveSettings (plan_request.h): where a plan's settings come from.
#include "planner/plan_request.h"

#include <string>

#include "core/invalid_argument.h"

namespace hfts::planner {

PlanSettings resolveSettings(const robot::RobotModel& robot, const PlanRequest& request) {
  PlanSettings s = request.settings ? *request.settings : defaultSettings(robot, request.preset);
  for (const auto& [name, value] : request.parameters) setSetting(s, name, value);
  if (request.iterations) {
    try {
      setSetting(s, "iterations", std::to_string(*request.iterations));
    } catch (const InvalidArgument& e) {
      throw InvalidArgument("iterations", e.problem());
    }
  }
  checkSettings(s);
  return s;
}

}  // namespace hfts::planner
