#pragma once
// Racing (parameter `threads`), internal to the planner library: copies of
// one search, each with its own seed in its own thread; the first plan
// stops the others.

#include <atomic>
#include <cstdint>
#include <functional>

#include "planner/plan_result.h"

namespace hfts::planner {

/// Copy `copy` of a race: searches with `seed` until `stop` is set.
using PlanOne =
    std::function<PlanResult(int copy, std::uint64_t seed, const std::atomic<bool>* stop)>;

/// `copies` searches race (planGrasp): copy i searches with
/// racingSeed(seed, i) in its own thread; the first plan stops the others.
/// `cancel` stops all of them. An exception of a copy is rethrown (every
/// copy checks the same request).
PlanResult race(std::uint64_t seed, const std::atomic<bool>* cancel, int copies,
                const PlanOne& planOne);

}  // namespace hfts::planner
