#pragma once
// One benchmark run as a CSV row, and the CSV file that holds them all.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "planner/grasp_motion_planner.h"

namespace hfts::bench {

/// What one planGrasp call reports, in the CSV's columns (docs/benchmarks.md).
struct RunRecord {
  std::string scene;
  std::string object;
  std::string algorithm;
  std::uint64_t seed = 0;
  bool success = false;
  std::string failure;    ///< toString(PlanFailure): "none" on success
  double time = 0.0;      ///< s, planning_time
  double cpu_time = 0.0;  ///< s, CPU time of the process during the run (all threads)
  std::uint64_t gs = 0;
  std::uint64_t vgs = 0;
  std::uint64_t gns = 0;
  double epsilon = 0.0;      ///< of the planned grasp; unused on failure
  double path_length = 0.0;  ///< smoothed, Eq. (3) metric; unused on failure
  std::uint64_t collision_checks = 0;
};

RunRecord makeRunRecord(const std::string& scene, const std::string& object,
                        const std::string& algorithm, std::uint64_t seed,
                        const planner::PlanResult& result, double cpuTime);

/// Writes the header and one row per record to `out.tmp`, then renames it
/// to `out`, so `out` always holds a complete file. Throws
/// std::runtime_error naming the file when it cannot be written.
void writeCsvAtomically(const std::filesystem::path& out, const std::vector<RunRecord>& records);

}  // namespace hfts::bench
