#include "racing.h"

#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "plan_diagnosis.h"

namespace hfts::planner {

std::uint64_t racingSeed(std::uint64_t seed, int copy) {
  if (copy == 0) return seed;
  std::uint64_t z = seed + 0x9e3779b97f4a7c15ULL * static_cast<std::uint64_t>(copy);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

PlanResult race(std::uint64_t seed, const std::atomic<bool>* cancel, int copies,
                const PlanOne& planOne) {
  const auto n = static_cast<std::size_t>(copies);
  std::atomic<bool> stop{false};
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<PlanResult> results(n);
  std::vector<std::exception_ptr> errors(n);
  std::size_t finished = 0;
  std::optional<std::size_t> winner;
  std::vector<std::thread> threads;
  threads.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
    threads.emplace_back([&, i] {
      PlanResult found;
      std::exception_ptr error;
      try {
        found = planOne(static_cast<int>(i), racingSeed(seed, static_cast<int>(i)), &stop);
      } catch (...) {
        error = std::current_exception();
      }
      const std::lock_guard<std::mutex> lock(mutex);
      if (found.success && !winner) winner = i;
      if (winner || error) stop = true;
      results[i] = std::move(found);
      errors[i] = error;
      ++finished;
      changed.notify_all();
    });
  {
    std::unique_lock<std::mutex> lock(mutex);
    while (finished < n)
      if (!changed.wait_for(lock, std::chrono::milliseconds(5), [&] { return finished == n; }) &&
          cancel != nullptr && cancel->load())
        stop = true;
  }
  for (std::thread& t : threads) t.join();
  for (const std::exception_ptr& error : errors)
    if (error) std::rethrow_exception(error);  // every copy checks the same request
  PlanResult result = std::move(results[winner.value_or(0)]);
  if (!winner && cancel != nullptr && cancel->load())
    return failed(std::move(result), {PlanFailure::kCancelled, "cancelled"});
  return result;
}

}  // namespace hfts::planner
