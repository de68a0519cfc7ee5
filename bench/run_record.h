#pragma once
// One benchmark run as a CSV row, and the CSV file that holds them all.

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "holdability.h"
#include "planner/grasp_motion_planner.h"

namespace hfts::bench {

/// What one planGrasp call reports, in the CSV's columns (docs/benchmarks.md).
/// What a run planned for: a scene, an object, a placement of the scene.
struct CaseName {
  std::string scene;
  std::string object;
  std::string placement = "target";
};

struct RunRecord {
  std::string scene;
  std::string object;
  std::string placement = "target";
  std::string algorithm;
  std::uint64_t seed = 0;
  /// The plan holds: planned and, where physics ran, the grasp as executed
  /// passed its checks and held (planner::Validation::holds).
  bool success = false;
  bool planned = false;  ///< the planner returned a plan
  /// With physics: the verdict of a plan (nullopt without a plan or physics).
  std::optional<bool> held;
  double held_fraction = 0.0;
  /// The first thing that failed: the check's problem, else the first
  /// dropping trial's "name: failure"; the lift direction taken.
  std::string physics_failure;
  std::string lift;
  std::string failure;    ///< toString(PlanFailure): "none" on success
  double cpu_time = 0.0;  ///< s, CPU time of the process during the run (all threads)
  /// PlannedGrasp's epsilon (at the contacts the closed hand touches),
  /// fingertip_error (m), planned_epsilon and penetration (m); unused on
  /// failure.
  double epsilon = 0.0;
  double fingertip_error = 0.0;
  double planned_epsilon = 0.0;
  double penetration = 0.0;
  /// The path's clearance as its proofs measured (PlanResult::clearance;
  /// none when sampled or failed).
  std::optional<double> clearance;
  /// The plan's statistics; the CSV's time, gs, vgs, gns, path_length and
  /// collision_checks columns are planning_time, goal_sampling_calls,
  /// valid_goal_samples, hfts_nodes_explored, path_length_smoothed and
  /// collision_checks.
  planner::PlanStatistics stats;
};

RunRecord makeRunRecord(const CaseName& c, const std::string& algorithm, std::uint64_t seed,
                        const planner::PlanResult& result, double cpuTime);

/// Writes the header and one row per record to `out` atomically
/// (core/atomic_file.h), so `out` always holds a complete file. Throws
/// std::runtime_error naming the file when it cannot be written.
void writeCsvAtomically(const std::filesystem::path& out, const std::vector<RunRecord>& records);

/// Whether the robot can hold an object where a case puts it
/// (bench::holdability), and how long that took to decide.
struct HoldabilityRecord {
  CaseName name;
  Holdability answer;
  double seconds = 0.0;
};

/// Writes one row per case (scene, object, placement, holdable, climbs, leaves,
/// stable, reached, hand_clear, epsilon, seconds, reason) to `out` atomically. Throws
/// std::runtime_error naming the file when it cannot be written.
void writeHoldabilityCsv(const std::filesystem::path& out,
                         const std::vector<HoldabilityRecord>& records);

/// The answers of a file writeHoldabilityCsv wrote, read back so that a
/// series of runs need not decide them again (hfts-bench --holdable-from).
class HoldabilityFile {
 public:
  /// Throws std::runtime_error naming the file, and the line where one is
  /// at fault, when it cannot be read, has no scene, object, placement and
  /// holdable columns, has a row with fewer fields or a holdable other than
  /// 0 or 1, or answers a case twice.
  explicit HoldabilityFile(const std::filesystem::path& path);
  /// The file's answer for `c`; throws std::runtime_error naming the file
  /// and the case when it has none.
  bool holdable(const CaseName& c) const;

 private:
  std::filesystem::path path_;
  std::map<std::tuple<std::string, std::string, std::string>, bool> answers_;
};

}  // namespace hfts::bench
