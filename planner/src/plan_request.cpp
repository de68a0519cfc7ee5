// planner::resolveSettings (plan_request.h): where a plan's settings come from.
#include "planner/plan_request.h"

#include <algorithm>
#include <string>

#include "core/invalid_argument.h"

namespace hfts::planner {

PlanSettings resolveSettings(const robot::RobotModel& robot, const PlanRequest& request) {
  // Typed settings are checked whole; defaults and values by name were
  // each checked as they were set (checking all 37 again cost a tenth of
  // a millisecond, a twentieth of a MotionBenchMaker plan).
  if (request.settings) checkSettings(*request.settings);
  PlanSettings s = request.settings ? *request.settings : defaultSettings(robot, request.preset);
  for (const auto& [name, value] : request.parameters) setSetting(s, name, value);
  if (request.iterations) {
    try {
      setSetting(s, "iterations", std::to_string(*request.iterations));
    } catch (const InvalidArgument& e) {
      throw InvalidArgument("iterations", e.problem());
    }
  }
  checkSettingOrder(s);
  return s;
}

double searchTimeLimit(double time_limit) {
  // Finishing took 0.15 s for the KR5's mug on the table, twice that on a
  // loaded machine (a run ended 0.13 s past a 10 s limit without a reserve).
  return time_limit - std::min(0.3, 0.05 * time_limit);
}

}  // namespace hfts::planner
