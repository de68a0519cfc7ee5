#pragma once
// Motion-only plans (motion_goal.h), internal to the planner library: the
// multi-tree CBiRRT from the start to the request's goals, with no grasp.
// planGrasp hands a request with goals here.

#include <atomic>
#include <chrono>

#include "planner/plan_request.h"
#include "planner/plan_result.h"
#include "planner/planning_world.h"

namespace hfts::planner {

/// The plan of a request with goals (PlanRequest::goals not empty), its
/// time counted from `began`; racing with `threads` > 1 as planGrasp.
/// Throws InvalidArgument for malformed goals (checkGoals) and for the
/// rrtconnect algorithm ("algorithm": it plans grasps only).
PlanResult planMotion(std::chrono::steady_clock::time_point began, const PlanningWorld& world,
                      const PlanRequest& request, const std::atomic<bool>* cancel);

}  // namespace hfts::planner
