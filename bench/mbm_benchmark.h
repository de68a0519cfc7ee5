#pragma once
// hfts-bench --mbm: the motion half measured on MotionBenchMaker's problems
// (docs/motionbenchmaker.md). Every problem of a folder of scenarios as
// published (DIR/<scenario>/sceneNNNN.yaml + requestNNNN.yaml) planned with
// the multi-tree planner towards its joint goal, beside OMPL's RRTConnect
// with FCL alone, one thread, one CSV row per run and a per-scenario table.

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "bench_options.h"

namespace hfts::bench {

struct MbmOptions {
  std::filesystem::path dir;           ///< the scenario folders
  std::filesystem::path robot;         ///< robot config (default robots/panda_mbm/panda_mbm.json)
  std::vector<std::string> scenarios;  ///< empty: every folder of dir
  int problems = 0;                    ///< the first N of each scenario; 0: all
  /// "coupled" and "paper" (the multi-tree planner, ":name=value" settings
  /// allowed), "rrtconnect" (OMPL's RRTConnect with FCL alone).
  std::vector<std::string> algorithms{"coupled", "rrtconnect"};
  double time_limit = 10.0;
  std::uint64_t seed = 1;
  std::filesystem::path csv;  ///< one row per run; empty: none
};

/// One problem of a scenario: its two files.
struct MbmProblemFiles {
  std::string scenario;
  std::string name;  ///< "0001"
  std::filesystem::path scene, request;
};

/// The problems under `dir` (every scenario folder, or those named),
/// sorted, at most `perScenario` each (0: all). Throws UsageError for a
/// missing folder, an unknown scenario, a scene without its request or a
/// folder without problems.
std::vector<MbmProblemFiles> findMbmProblems(const std::filesystem::path& dir,
                                             const std::vector<std::string>& scenarios,
                                             int perScenario);

/// Runs the benchmark, prints the table to `out`; returns the exit status
/// (0). Throws UsageError for bad options, robot::SceneError for a problem
/// file that cannot be read.
int runMbm(const MbmOptions& options, std::ostream& out);

}  // namespace hfts::bench
