#pragma once
// Benchmark results in OMPL's log format, written by OMPL's own
// ompl::tools::Benchmark::saveResultsToStream, so that OMPL's
// ompl_benchmark_statistics.py turns them into a database for Planner
// Arena (plannerarena.org). One log is one OMPL "experiment": one scene
// and object, with each algorithm as a planner (docs/benchmarks.md).

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "run_record.h"

namespace hfts::bench {

/// What a log says about its experiment besides the runs.
struct LogExperiment {
  std::string scene;
  std::string object;
  double time_limit = 0.0;  ///< s per run
  int runs = 0;             ///< per algorithm
  std::string setup;        ///< free text: how the runs were made
  std::chrono::system_clock::time_point started;
  double seconds = 0.0;  ///< spent on the runs
};

/// Writes the runs of `records` with the experiment's scene and object, one
/// planner per entry of `algorithms` (in that order), to `file`
/// atomically. Run properties: time, solved, status (OMPL's planner
/// status), cpu time, seed, GS, VGS, GNS, grasp epsilon, solution length
/// and collision checks; epsilon and length are empty for failed runs.
/// Throws std::runtime_error naming the file when it cannot be written.
void writeOmplBenchmarkLog(const std::filesystem::path& file, const LogExperiment& experiment,
                           const std::vector<RunRecord>& records,
                           const std::vector<std::string>& algorithms);

}  // namespace hfts::bench
