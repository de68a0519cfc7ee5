#include "ompl_benchmark_log.h"

#include <ompl/base/PlannerStatus.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/config.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/tools/benchmark/Benchmark.h>
#include <ompl/tools/benchmark/MachineSpecs.h>

#include <map>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"

namespace hfts::bench {
namespace {

namespace ob = ompl::base;
namespace ot = ompl::tools;

/// OMPL's Benchmark with data recorded elsewhere: it runs nothing, only
/// its saveResultsToStream() is used, so the format is OMPL's own.
class RecordedBenchmark : public ot::Benchmark {
 public:
  RecordedBenchmark(ompl::geometric::SimpleSetup& setup, CompleteExperiment experiment)
      : Benchmark(setup) {
    exp_ = std::move(experiment);
  }
};

/// OMPL's planner status of a run, for Planner Arena's status chart.
ob::PlannerStatus::StatusType statusOf(const std::string& failure) {
  static const std::map<std::string, ob::PlannerStatus::StatusType> statuses = {
      {"none", ob::PlannerStatus::EXACT_SOLUTION},
      {"time_limit", ob::PlannerStatus::TIMEOUT},
      // Ran to the time limit without a grasp the arm reaches collision-free.
      {"no_valid_goal", ob::PlannerStatus::TIMEOUT},
      {"no_stable_grasp_clear_of_support", ob::PlannerStatus::INVALID_GOAL},
      // A path to a grasp the physics check did not see hold: OMPL's
      // nearest status is a solution that does not reach the goal.
      {"not_held", ob::PlannerStatus::APPROXIMATE_SOLUTION},
      {"cancelled", ob::PlannerStatus::ABORT},
      {"start_in_collision", ob::PlannerStatus::INVALID_START},
      {"object_in_collision", ob::PlannerStatus::INVALID_GOAL},
      {"object_unreachable", ob::PlannerStatus::INVALID_GOAL},
      {"unknown_object", ob::PlannerStatus::INVALID_GOAL}};
  const auto it = statuses.find(failure);
  return it == statuses.end() ? ob::PlannerStatus::UNKNOWN : it->second;
}

std::string text(double value) {
  std::ostringstream out;
  out.precision(9);
  out << value;
  return out.str();
}

ot::Benchmark::RunProperties propertiesOf(const RunRecord& r) {
  ot::Benchmark::RunProperties p;
  p["time REAL"] = text(r.stats.planning_time);
  p["solved BOOLEAN"] = r.success ? "1" : "0";
  p["status ENUM"] = std::to_string(static_cast<int>(statusOf(r.failure)));
  p["cpu time REAL"] = text(r.cpu_time);
  p["seed INTEGER"] = std::to_string(r.seed);
  p["goal sampling calls INTEGER"] = std::to_string(r.stats.goal_sampling_calls);
  p["valid goal samples INTEGER"] = std::to_string(r.stats.valid_goal_samples);
  p["hfts nodes explored INTEGER"] = std::to_string(r.stats.hfts_nodes_explored);
  p["collision checks INTEGER"] = std::to_string(r.stats.collision_checks);
  // Failed runs have no grasp and no path: empty, which the statistics
  // script stores as NULL.
  p["grasp epsilon REAL"] = r.success ? text(r.epsilon) : "";
  p["solution length REAL"] = r.success ? text(r.stats.path_length_smoothed) : "";
  return p;
}

ot::Benchmark::PlannerExperiment plannerOf(const std::string& algorithm,
                                           const LogExperiment& experiment,
                                           const std::vector<RunRecord>& records) {
  ot::Benchmark::PlannerExperiment planner;
  planner.name = algorithm;
  for (const RunRecord& r : records)
    if (r.algorithm == algorithm && r.scene == experiment.scene && r.object == experiment.object)
      planner.runs.push_back(propertiesOf(r));
  return planner;
}

/// Debian's OMPL 1.5.2 is built with an empty OMPL_VERSION string, which
/// leaves the log's first line without the version that Planner Arena
/// shows; fill it in from the version numbers.
std::string withVersion(std::string log) {
  const std::string bare = "OMPL version \n";
  if (log.rfind(bare, 0) == 0)
    log.replace(0, bare.size(),
                "OMPL version " + std::to_string(OMPL_MAJOR_VERSION) + "." +
                    std::to_string(OMPL_MINOR_VERSION) + "." + std::to_string(OMPL_PATCH_VERSION) +
                    "\n");
  return log;
}

}  // namespace

void writeOmplBenchmarkLog(const std::filesystem::path& file, const LogExperiment& experiment,
                           const std::vector<RunRecord>& records,
                           const std::vector<std::string>& algorithms) {
  ot::Benchmark::CompleteExperiment e;
  e.name = experiment.scene + "_" + experiment.object;  // one word: the parser takes the last
  e.parameters["scene TEXT"] = experiment.scene;
  e.parameters["object TEXT"] = experiment.object;
  for (const std::string& algorithm : algorithms)
    e.planners.push_back(plannerOf(algorithm, experiment, records));
  e.maxTime = experiment.time_limit;
  e.maxMem = 0.0;  // no memory limit
  e.runCount = static_cast<unsigned>(experiment.runs);
  e.startTime = experiment.started;
  e.totalDuration = experiment.seconds;
  e.setupInfo = experiment.setup;
  e.seed = 1;  // seeds 1..runs, see the runs' seed property
  e.host = ompl::machine::getHostname();
  e.cpuInfo = ompl::machine::getCPUInfo();
  // Benchmark needs a setup to run planners; saving does not use it.
  ompl::geometric::SimpleSetup unused(std::make_shared<ob::RealVectorStateSpace>(1));
  const RecordedBenchmark benchmark(unused, std::move(e));
  std::ostringstream out;
  if (!benchmark.saveResultsToStream(out))
    throw std::runtime_error("no runs to write to '" + file.string() + "'");
  core::writeFileAtomically(file, withVersion(out.str()));
}

}  // namespace hfts::bench
