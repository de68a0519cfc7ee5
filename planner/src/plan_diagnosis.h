#pragma once
// What a plan's result says, internal to the planner library: why a search
// found nothing (failureOf), the grasp it found as the result describes it
// (describeGrasp), and a failed result (failed).

#include <atomic>
#include <string>
#include <utility>

#include "plan_problem.h"
#include "plan_search.h"

namespace hfts::planner {

/// Why a search found nothing.
std::pair<PlanFailure, std::string> failureOf(const SearchOutcome& found,
                                              const std::atomic<bool>* cancel);

/// The goal's grasp for the result: the contacts the closed hand touches,
/// their epsilon, the planned contacts and the fingertips' depth.
PlannedGrasp describeGrasp(const Problem& p, const GoalSample& goal);

/// `result` with its failure and message.
PlanResult failed(PlanResult result, std::pair<PlanFailure, std::string> why);

}  // namespace hfts::planner
