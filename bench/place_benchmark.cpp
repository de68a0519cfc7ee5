#include "place_benchmark.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <ostream>
#include <sstream>

#include "bench_options.h"
#include "core/atomic_file.h"
#include "core/invalid_argument.h"
#include "planner/grasp_motion_planner.h"
#include "robot/scene.h"

namespace hfts::bench {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// One run of one task with one placement search.
struct PlaceRun {
  std::string task, search;
  std::uint64_t seed = 0;
  bool planned = false;  ///< the planner returned a pick and place
  std::string reason;    ///< its failure ("none" when planned)
  bool held = false;     ///< physics: in the hand through the carry
  bool placed = false;   ///< physics: stayed where the hand let go of it
  bool stood = false;    ///< physics: held, and at rest after the retreat
  std::string physics_failure;
  double time = 0.0;        ///< s, the plan's planning_time
  double place_time = 0.0;  ///< s, its place stage
  double rest_displacement = 0.0, rest_rotation = 0.0, place_displacement = 0.0;
  double duration = 0.0;          ///< s, the trajectory's
  std::uint64_t place_tried = 0;  ///< placements rejected

  bool success(bool physics) const { return planned && (!physics || (held && placed)); }
};

double numberIn(const json& j, const std::string& where) {
  if (!j.is_number()) throw UsageError(where + ": must be a number");
  return j.get<double>();
}

planner::PlaceGoal placeGoalOf(const json& j, const std::string& where) {
  if (!j.is_object()) throw UsageError(where + ": must be an object {\"on\": obstacle, ...}");
  planner::PlaceGoal goal;
  for (const auto& [key, value] : j.items()) {
    if (key == "on" && value.is_string()) {
      goal.on = value.get<std::string>();
    } else if (key == "upright" && value.is_boolean()) {
      goal.upright = value.get<bool>();
    } else if (key == "area" && value.is_object() && value.contains("min") &&
               value.contains("max") && value["min"].size() == 2 && value["max"].size() == 2) {
      goal.area =
          Eigen::AlignedBox2d(Eigen::Vector2d(numberIn(value["min"][0], where + ".area.min"),
                                              numberIn(value["min"][1], where + ".area.min")),
                              Eigen::Vector2d(numberIn(value["max"][0], where + ".area.max"),
                                              numberIn(value["max"][1], where + ".area.max")));
    } else {
      throw UsageError(where + "." + key +
                       ": unknown or malformed (on: a name, area: {min: [x, y], max: [x, y]}, "
                       "upright: a boolean)");
    }
  }
  if (goal.on.empty()) throw UsageError(where + ".on: names the support to place on");
  return goal;
}

std::string fixed(double value, int digits) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(digits) << value;
  return text.str();
}

double median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

std::string csvOf(const std::vector<PlaceRun>& runs, const std::string& robot, bool physics) {
  std::ostringstream csv;
  csv << "task,robot,search,seed,success,planned,reason,held,placed,stood,physics_failure,time,"
         "place_time,"
         "duration,rest_displacement,rest_rotation,place_displacement,placements_rejected\n";
  for (const PlaceRun& r : runs) {
    std::string failure = r.physics_failure;
    std::replace(failure.begin(), failure.end(), ',', ';');
    csv << r.task << "," << robot << "," << r.search << "," << r.seed << ","
        << (r.success(physics) ? 1 : 0) << "," << (r.planned ? 1 : 0) << "," << r.reason << ","
        << (r.held ? 1 : 0) << "," << (r.placed ? 1 : 0) << "," << (r.stood ? 1 : 0) << ","
        << failure << "," << fixed(r.time, 4) << "," << fixed(r.place_time, 4) << ","
        << fixed(r.duration, 3) << "," << fixed(r.rest_displacement, 5) << ","
        << fixed(r.rest_rotation, 4) << "," << fixed(r.place_displacement, 5) << ","
        << r.place_tried << "\n";
  }
  return csv.str();
}

/// A --searches entry: "coupled" or "decoupled", optionally
/// ":held_speed=F" (the lift's held speed, planner/lift.h).
struct SearchSpec {
  planner::PlaceSearch search = planner::PlaceSearch::kCoupled;
  planner::LiftOptions lift;
};

SearchSpec searchSpecOf(const std::string& text) {
  SearchSpec spec;
  const std::string name = text.substr(0, text.find(':'));
  if (name != "coupled" && name != "decoupled")
    throw UsageError("--searches: unknown '" + name + "' in '" + text +
                     "' (valid: coupled, decoupled, each with :held_speed=F)");
  spec.search =
      name == "coupled" ? planner::PlaceSearch::kCoupled : planner::PlaceSearch::kDecoupled;
  for (std::size_t at = text.find(':'); at != std::string::npos;) {
    const std::size_t next = text.find(':', at + 1);
    const std::string setting =
        text.substr(at + 1, next == std::string::npos ? next : next - at - 1);
    const std::string prefix = "held_speed=";
    if (setting.rfind(prefix, 0) != 0)
      throw UsageError("--searches: unknown setting '" + setting + "' in '" + text +
                       "' (valid: held_speed=F)");
    try {
      std::size_t used = 0;
      spec.lift.held_speed = std::stod(setting.substr(prefix.size()), &used);
      if (used != setting.size() - prefix.size()) throw std::invalid_argument("trailing text");
      planner::checkLiftOptions(spec.lift);
    } catch (const std::exception&) {
      throw UsageError("--searches: '" + text + "': held_speed must be a number in (0, 1]");
    }
    at = next;
  }
  return spec;
}

PlaceRun runOnce(const planner::PlanningWorld& world, const PlaceTask& task,
                 const robot::Scene& scene, const std::string& search, std::uint64_t seed,
                 const PlaceOptions& o) {
  const SearchSpec spec = searchSpecOf(search);
  planner::PlanRequest request;
  request.scene = scene;
  request.object = task.object;
  request.place = task.place;
  request.place_search = spec.search;
  request.lift = spec.lift;
  request.seed = seed;
  request.time_limit = o.time_limit;
  const planner::PlanResult result = planner::planGrasp(world, request);
  PlaceRun run;
  run.task = task.name;
  run.search = search;
  run.seed = seed;
  run.planned = result.success;
  run.reason = planner::toString(result.failure);
  run.time = result.stats.planning_time;
  run.place_time = result.stats.place_time;
  run.place_tried = result.place_rejected.total();
  run.duration = result.trajectory.duration;
  if (result.success && o.physics && !result.trajectory.points.empty()) {
    const physics::PlaceVerdict v = planner::simulatePlace(world, request, result);
    run.held = v.held;
    run.placed = v.placed;
    run.stood = v.held && v.stood;
    run.physics_failure = v.failure;
    run.rest_displacement = v.rest_displacement;
    run.rest_rotation = v.rest_rotation;
    run.place_displacement = v.place_displacement;
  } else if (result.success && o.physics) {
    run.physics_failure = "no trajectory to simulate";
  }
  return run;
}

/// "k/n (lo-hi %)".
std::string rate(int k, int n) {
  const auto [lo, hi] = wilsonInterval(k, n);
  return std::to_string(k) + "/" + std::to_string(n) + " (" + fixed(100.0 * lo, 0) + "-" +
         fixed(100.0 * hi, 0) + " %)";
}

void printTable(std::ostream& out, const std::vector<PlaceRun>& runs,
                const std::vector<std::string>& tasks, const std::vector<std::string>& searches,
                bool physics) {
  out << "| task | search | success" << (physics ? " (held, placed)" : "")
      << (physics ? " | held, standing after the retreat" : "")
      << " | planned | median time (s) | median place stage (s) |\n|---|---|---|"
      << (physics ? "---|" : "") << "---|---|---|\n";
  const auto row = [&](const std::string& task, const std::string& search) {
    int k = 0, stood = 0, planned = 0, n = 0;
    std::vector<double> times, placing;
    for (const PlaceRun& r : runs) {
      if ((task != "all" && r.task != task) || r.search != search) continue;
      ++n;
      k += r.success(physics) ? 1 : 0;
      planned += r.planned ? 1 : 0;
      stood += r.planned && r.stood ? 1 : 0;
      times.push_back(r.time);
      if (r.place_time > 0.0) placing.push_back(r.place_time);
    }
    out << "| " << task << " | " << search << " | " << rate(k, n) << " | "
        << (physics ? rate(stood, n) + " | " : "") << planned << "/" << n << " | "
        << fixed(median(times), 2) << " | " << fixed(median(placing), 2) << " |\n";
  };
  for (const std::string& task : tasks)
    for (const std::string& search : searches) row(task, search);
  for (const std::string& search : searches) row("all", search);
}

}  // namespace

std::pair<double, double> wilsonInterval(int k, int n) {
  if (n <= 0) return {0.0, 1.0};
  constexpr double z = 1.959963984540054;
  const double p = static_cast<double>(k) / n, z2 = z * z / n;
  const double centre = (p + z2 / 2.0) / (1.0 + z2);
  const double half = z * std::sqrt(p * (1.0 - p) / n + z * z / (4.0 * n * n)) / (1.0 + z2);
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

std::vector<PlaceTask> readPlaceTasks(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw UsageError("--place: cannot read '" + file.string() + "'");
  json doc;
  try {
    doc = json::parse(in);
  } catch (const json::exception& e) {
    throw UsageError("--place: '" + file.string() + "' is not JSON: " + e.what());
  }
  if (!doc.is_object() || !doc.contains("tasks") || !doc["tasks"].is_array() ||
      doc["tasks"].empty())
    throw UsageError("--place: '" + file.string() + "' has no \"tasks\" array");
  std::vector<PlaceTask> tasks;
  for (std::size_t i = 0; i < doc["tasks"].size(); ++i) {
    const json& t = doc["tasks"][i];
    const std::string where = "--place: tasks[" + std::to_string(i) + "]";
    if (!t.is_object()) throw UsageError(where + ": must be an object");
    PlaceTask task;
    for (const char* key : {"name", "scene", "object"})
      if (!t.contains(key) || !t[key].is_string() || t[key].get<std::string>().empty())
        throw UsageError(where + "." + key + ": must be a non-empty string");
    task.name = t["name"].get<std::string>();
    task.scene = t["scene"].get<std::string>();
    task.object = t["object"].get<std::string>();
    if (t.contains("at")) {
      if (!t["at"].is_string()) throw UsageError(where + ".at: must be a placement's name");
      task.at = t["at"].get<std::string>();
    }
    if (!t.contains("place")) throw UsageError(where + ".place: missing");
    task.place = placeGoalOf(t["place"], where + ".place");
    for (const auto& [key, value] : t.items())
      if (key != "name" && key != "scene" && key != "object" && key != "at" && key != "place")
        throw UsageError(where + "." + key + ": unknown (name, scene, object, at, place)");
    for (const PlaceTask& other : tasks)
      if (other.name == task.name) throw UsageError(where + ".name: '" + task.name + "' twice");
    tasks.push_back(std::move(task));
  }
  return tasks;
}

int runPlaceBenchmark(const PlaceOptions& o, std::ostream& out) {
  checkRunsAndTimeLimit(o.runs, o.time_limit);
  for (const std::string& s : o.searches) searchSpecOf(s);
  std::vector<PlaceTask> tasks = readPlaceTasks(o.tasks);
  std::vector<std::string> names;
  for (const PlaceTask& t : tasks) names.push_back(t.name);
  requireKnown(o.names, names, "task");
  if (!o.names.empty()) {
    tasks.erase(std::remove_if(tasks.begin(), tasks.end(),
                               [&](const PlaceTask& t) {
                                 return std::find(o.names.begin(), o.names.end(), t.name) ==
                                        o.names.end();
                               }),
                tasks.end());
  }
  // Every scene and place goal checked before the first run.
  std::map<std::string, robot::Scene> scenes;
  for (const PlaceTask& t : tasks) {
    robot::Scene scene = robot::loadScene(o.tasks.parent_path() / (t.scene + ".json"));
    scene.name = t.scene;
    try {
      scene = scene.withPlacement(t.at);
      planner::placeRegion(scene, t.place);
    } catch (const std::exception& e) {
      throw UsageError("--place: task '" + t.name + "': " + e.what());
    }
    scenes[t.name] = std::move(scene);
  }
  std::vector<std::string> skipped;
  const auto world = planner::PlanningWorld::load(o.robot, o.db, &skipped);
  for (const PlaceTask& t : tasks)
    if (world->object(t.object) == nullptr)
      throw UsageError("--place: task '" + t.name + "': object '" + t.object +
                       "' has no database in " + o.db.string());

  std::vector<PlaceRun> runs;
  const std::string robotName = world->robot().name();
  if (!o.csv.empty()) core::writeFileAtomically(o.csv, csvOf(runs, robotName, o.physics));
  for (const PlaceTask& t : tasks)
    for (const std::string& search : o.searches)
      for (int i = 0; i < o.runs; ++i) {
        runs.push_back(runOnce(*world, t, scenes[t.name], search,
                               o.first_seed + static_cast<std::uint64_t>(i), o));
        if (!o.csv.empty()) core::writeFileAtomically(o.csv, csvOf(runs, robotName, o.physics));
      }
  std::vector<std::string> order;
  for (const PlaceTask& t : tasks) order.push_back(t.name);
  out << "pick and place, robot " << robotName << ", " << o.runs << " runs per task and search, "
      << fixed(o.time_limit, 0) << " s each, one thread\n\n";
  printTable(out, runs, order, o.searches, o.physics);
  if (!o.csv.empty()) out << "\n" << runs.size() << " runs written to " << o.csv.string() << "\n";
  return 0;
}

}  // namespace hfts::bench
