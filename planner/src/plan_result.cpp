#include "planner/plan_result.h"

namespace hfts::planner {

const char* toString(PlanFailure failure) {
  switch (failure) {
    case PlanFailure::kNone:
      return "none";
    case PlanFailure::kTimeLimit:
      return "time_limit";
    case PlanFailure::kCancelled:
      return "cancelled";
    case PlanFailure::kStartInCollision:
      return "start_in_collision";
    case PlanFailure::kObjectInCollision:
      return "object_in_collision";
    case PlanFailure::kObjectUnreachable:
      return "object_unreachable";
    case PlanFailure::kUnknownObject:
      return "unknown_object";
    case PlanFailure::kNoValidGoal:
      return "no_valid_goal";
    case PlanFailure::kNoStableGraspClearOfSupport:
      return "no_stable_grasp_clear_of_support";
    case PlanFailure::kGoalInCollision:
      return "goal_in_collision";
    case PlanFailure::kLiftBlocked:
      return "lift_blocked";
    case PlanFailure::kNoStablePlacement:
      return "no_stable_placement";
    case PlanFailure::kPlaceNotReached:
      return "place_not_reached";
  }
  return "unknown";
}

}  // namespace hfts::planner
