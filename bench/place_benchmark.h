#pragma once
// hfts-bench --place: pick and place measured (docs/placement.md). Every
// task of a task file (a scene beside it, the object, where it stands, the
// place goal) planned with the coupled placement search and the decoupled
// one (a stable placement drawn first, then planned to), one thread, and
// each plan simulated whole in MuJoCo: success is a plan whose object
// stays in the hand through the carry and stays where the hand let go of
// it. One CSV row per run, a table with Wilson intervals.

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "planner/place_goal.h"

namespace hfts::bench {

/// One task of a task file.
struct PlaceTask {
  std::string name;
  std::string scene;          ///< SCENE.json beside the task file
  std::string object;         ///< an object database
  std::string at = "target";  ///< where it stands: "target" or a placement of the scene
  planner::PlaceGoal place;
};

/// The tasks of `file` ({"tasks": [{name, scene, object, at, place: {on,
/// area: {min, max}, upright}}]}). Throws UsageError naming the task and
/// field for a file that cannot be read or a malformed task.
std::vector<PlaceTask> readPlaceTasks(const std::filesystem::path& file);

struct PlaceOptions {
  std::filesystem::path tasks;     ///< the task file
  std::filesystem::path robot;     ///< robot config
  std::filesystem::path db;        ///< object databases and hand maps
  std::vector<std::string> names;  ///< tasks to run; empty: all
  std::vector<std::string> searches{"coupled", "decoupled"};
  int runs = 10;
  std::uint64_t first_seed = 1;
  double time_limit = 30.0;
  bool physics = true;        ///< simulate every plan (success: held and placed)
  std::filesystem::path csv;  ///< one row per run (rewritten after each)
};

/// The Wilson score interval (95 %) of k successes in n trials.
std::pair<double, double> wilsonInterval(int k, int n);

/// Runs the benchmark and prints the table to `out`; returns the exit
/// status (0). Throws UsageError for bad options or tasks.
int runPlaceBenchmark(const PlaceOptions& options, std::ostream& out);

}  // namespace hfts::bench
