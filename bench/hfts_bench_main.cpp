// hfts-bench: the paper's experiments (Sec. IV). Plans every combination of
// scene, object, algorithm and seed, writes one CSV row per run and prints
// a per-algorithm summary; --experiment also writes OMPL benchmark logs
// and the plots. See docs/benchmarks.md.
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bench_options.h"
#include "bench_report.h"
#include "experiment_design.h"
#include "holdability.h"
#include "mbm_benchmark.h"
#include "ompl_benchmark_log.h"
#include "place_benchmark.h"
#include "planner/grasp_motion_planner.h"
#include "plot_script.h"
#include "robot/scene.h"
#include "run_record.h"

namespace {

namespace fs = std::filesystem;
using hfts::bench::Algorithm;
using hfts::bench::RunRecord;
using hfts::bench::UsageError;
using hfts::planner::PlanningWorld;
using hfts::robot::Scene;

struct Options {
  std::string db, robot, sceneDir, out, experiment, outDir, holdability, holdableFrom, mbm, place,
      python = "/usr/bin/python3";
  std::vector<std::string> tasks;                             ///< --place: these tasks only
  std::vector<std::string> searches{"coupled", "decoupled"};  ///< --place: placement searches
  std::vector<std::string> scenarios;                         ///< --mbm: scenario folders
  int problems = 0;  ///< --mbm: the first N of each scenario
  std::vector<std::string> scenes, objects, placements{"target"},
      algorithms{"coupled", "decoupled20", "decoupled60", "decoupled100"};
  int runs = 10;
  int firstSeed = 1;
  double timeLimit = 60.0;
  bool quick = false, noPlots = false, holdableOnly = false, noPhysics = false;
  std::string commandLine;
  std::vector<hfts::bench::SceneObjects> designCases;  ///< --experiment's objects per scene
};

/// Options the user gave explicitly (they override an experiment's design).
struct Given {
  CLI::Option *scenes, *objects, *placements, *algorithms, *runs, *timeLimit;
};

/// One scene with one object at one placement (the scene's target pose, or
/// another of its placements, made the target's).
struct Case {
  Scene scene;
  std::string object;
  std::string placement;
};

/// Everything the runs need, checked: a bad argument never costs a run.
struct Experiment {
  /// Every plan's grasp is checked again and simulated: success is a plan
  /// that holds (planner::Validation::holds).
  bool physics = true;
  std::vector<Algorithm> algorithms;
  std::vector<Case> cases;
  std::shared_ptr<const PlanningWorld> world;
  int runs = 0;
  int firstSeed = 1;  ///< seeds firstSeed .. firstSeed + runs - 1
  double timeLimit = 0.0;
  fs::path csv;
  fs::path outDir;  ///< experiment mode only: logs and plots go here
  /// Cases left out by --holdable-only or --holdable-from (the object
  /// cannot be held there).
  std::vector<Case> unholdable;
};

Given addOptions(CLI::App& app, Options& o) {
  Given g{};
  app.add_option("--db", o.db, "Object databases and hand map (default build/databases)")
      ->type_name("DIR");
  app.add_option("--robot", o.robot, "Robot config (default robots/kr5_sdh/kr5_sdh.json)")
      ->type_name("CONFIG");
  app.add_option("--scene-dir", o.sceneDir, "Where scene S is S.json (default objects/scenes)")
      ->type_name("DIR");
  g.scenes = app.add_option("--scenes", o.scenes,
                            "Scenes to plan in (default: every scene in --scene-dir)")
                 ->delimiter(',');
  g.objects = app.add_option("--objects", o.objects,
                             "Objects placed at each scene's target pose (default: each scene's "
                             "target)")
                  ->delimiter(',');
  g.placements =
      app.add_option("--placements", o.placements,
                     "Where each object stands: target (the scene's target pose), names of the "
                     "scenes' placements, or all")
          ->delimiter(',')
          ->capture_default_str();
  g.algorithms = app.add_option("--algorithms", o.algorithms,
                                "coupled, decoupledN (N iterations/level), rrtconnect[N]")
                     ->delimiter(',')
                     ->capture_default_str();
  g.runs = app.add_option("--runs", o.runs, "Runs per combination, with seeds F..F+N-1")
               ->capture_default_str();
  app.add_option("--first-seed", o.firstSeed, "F: the first seed of each combination's runs")
      ->check(CLI::Range(0, 1 << 30))
      ->capture_default_str();
  g.timeLimit =
      app.add_option("--time-limit", o.timeLimit, "Seconds per run")->capture_default_str();
  auto* out = app.add_option("--out", o.out, "CSV file, one row per run (rewritten after each run)")
                  ->type_name("FILE");
  auto* experiment =
      app.add_option("--experiment", o.experiment,
                     "Run a named experiment (paper, zoo): CSV, OMPL logs and plots in --out-dir")
          ->excludes(out)
          ->type_name("NAME");
  app.add_option("--out-dir", o.outDir, "Where --experiment writes its results")
      ->needs(experiment)
      ->type_name("DIR");
  app.add_flag("--quick", o.quick, "With --experiment: its small variant (CI)")->needs(experiment);
  app.add_option("--python", o.python, "Python with numpy and matplotlib for the plots")
      ->needs(experiment)
      ->capture_default_str();
  app.add_flag("--no-plots", o.noPlots, "With --experiment: skip the plots")->needs(experiment);
  app.add_flag("--no-physics", o.noPhysics,
               "Do not simulate the plans (success is then a plan, not a plan that holds)");
  app.add_flag("--holdable-only", o.holdableOnly,
               "Plan only where the robot can hold the object (a collision-free grasp "
               "configuration exists, docs/robots.md#which-objects-a-robot-can-hold); the "
               "others are listed");
  auto* holdability =
      app.add_option("--holdability", o.holdability,
                     "CSV file: whether the robot can hold each case's object, and why not")
          ->type_name("FILE");
  app.add_option("--holdable-from", o.holdableFrom,
                 "Like --holdable-only, with the answers read from a file --holdability wrote "
                 "(for the same robot) instead of decided again")
      ->excludes(holdability)
      ->type_name("FILE");
  auto* mbm = app.add_option("--mbm", o.mbm,
                             "MotionBenchMaker mode: plan every problem of the scenario folders "
                             "in DIR (docs/motionbenchmaker.md); --robot defaults to "
                             "robots/panda_mbm/panda_mbm.json, --algorithms to "
                             "coupled,rrtconnect, --time-limit to 10")
                  ->type_name("DIR")
                  ->excludes(experiment);
  app.add_option("--scenarios", o.scenarios, "With --mbm: these scenario folders only")
      ->delimiter(',')
      ->needs(mbm);
  app.add_option("--problems", o.problems, "With --mbm: the first N problems of each scenario")
      ->needs(mbm);
  auto* place = app.add_option("--place", o.place,
                               "Pick and place mode: plan every task of the task FILE "
                               "(objects/pick_and_place/tasks.json) with each placement search "
                               "and simulate it (docs/placement.md); --time-limit defaults to 30")
                    ->type_name("FILE")
                    ->excludes(experiment)
                    ->excludes(mbm);
  app.add_option("--tasks", o.tasks, "With --place: these tasks only")
      ->delimiter(',')
      ->needs(place);
  app.add_option("--searches", o.searches,
                 "With --place: coupled, decoupled, each optionally with :held_speed=F")
      ->delimiter(',')
      ->needs(place)
      ->capture_default_str();
  return g;
}

/// --mbm: the MotionBenchMaker mode, with its own defaults.
int benchmarkMbm(const Options& o, const Given& given) {
  hfts::bench::MbmOptions m;
  m.dir = o.mbm;
  m.robot = hfts::bench::resolveDefault(o.robot, "robots/panda_mbm/panda_mbm.json");
  m.scenarios = o.scenarios;
  m.problems = o.problems;
  if (given.algorithms->count() > 0) m.algorithms = o.algorithms;
  if (given.timeLimit->count() > 0) m.time_limit = o.timeLimit;
  m.seed = static_cast<std::uint64_t>(o.firstSeed);
  m.csv = o.out;
  return hfts::bench::runMbm(m, std::cout);
}

/// --place: the pick and place mode, with its own defaults.
int benchmarkPlace(const Options& o, const Given& given) {
  hfts::bench::PlaceOptions p;
  p.tasks = o.place;
  p.robot = hfts::bench::resolveDefault(o.robot, "robots/kr5_sdh/kr5_sdh.json");
  p.db = hfts::bench::resolveDefault(o.db, "build/databases");
  p.names = o.tasks;
  p.searches = o.searches;
  p.runs = o.runs;
  p.first_seed = static_cast<std::uint64_t>(o.firstSeed);
  if (given.timeLimit->count() > 0) p.time_limit = o.timeLimit;
  p.physics = !o.noPhysics;
  p.csv = o.out;
  return hfts::bench::runPlaceBenchmark(p, std::cout);
}

/// --experiment fills what the user did not give.
void applyDesign(Options& o, const Given& given) {
  if (o.experiment.empty()) {
    if (o.out.empty()) throw UsageError("give --out FILE, or --experiment NAME with --out-dir DIR");
    return;
  }
  if (o.outDir.empty()) throw UsageError("--experiment needs --out-dir DIR");
  const hfts::bench::ExperimentDesign d = hfts::bench::experimentDesign(o.experiment, o.quick);
  o.designCases = d.cases;
  if (given.scenes->count() == 0)
    for (const auto& c : d.cases) o.scenes.push_back(c.scene);
  if (given.placements->count() == 0) o.placements = d.placements;
  if (given.algorithms->count() == 0) o.algorithms = d.algorithms;
  if (given.runs->count() == 0) o.runs = d.runs;
  if (given.timeLimit->count() == 0) o.timeLimit = d.time_limit;
  o.out = (fs::path(o.outDir) / "results.csv").string();
}

std::vector<Scene> loadScenes(const Options& o) {
  const fs::path dir = hfts::bench::resolveDefault(o.sceneDir, "objects/scenes");
  const std::vector<std::string> available = hfts::bench::sceneNamesIn(dir);
  if (available.empty()) throw std::runtime_error("no *.json scene in '" + dir.string() + "'");
  hfts::bench::requireKnown(o.scenes, available, "scene");
  std::vector<Scene> scenes;
  for (const std::string& name : o.scenes.empty() ? available : o.scenes) {
    scenes.push_back(hfts::robot::loadScene(dir / (name + ".json")));
    scenes.back().name = name;  // the CSV names scenes as the command line does
  }
  return scenes;
}

std::shared_ptr<const PlanningWorld> loadWorld(const Options& o) {
  const fs::path db = hfts::bench::resolveDefault(o.db, "build/databases");
  std::vector<std::string> skipped;
  auto world = PlanningWorld::load(
      hfts::bench::resolveDefault(o.robot, "robots/kr5_sdh/kr5_sdh.json"), db, &skipped);
  for (const std::string& why : skipped)
    std::cerr << "hfts-bench: skipped an object database: " << why << "\n";
  return world;
}

/// The objects of a scene: --objects, else the experiment's (none named:
/// every object of the databases), else its target.
std::vector<std::string> objectsFor(const Scene& scene, const PlanningWorld& world,
                                    const Options& o) {
  if (!o.objects.empty()) return o.objects;
  for (const auto& c : o.designCases)
    if (c.scene == scene.name) return c.objects.empty() ? world.objectNames() : c.objects;
  return {scene.target_object};
}

/// The placements of a scene that --placements names ("all": every one).
std::vector<std::string> placementsOf(const Scene& scene, const Options& o) {
  std::vector<std::string> all{"target"};
  for (const hfts::robot::Placement& p : scene.placements) all.push_back(p.name);
  if (o.placements.size() == 1 && o.placements.front() == "all") return all;
  try {
    hfts::bench::requireKnown(o.placements, all, "placement");
  } catch (const UsageError& e) {
    throw UsageError("--placements: in scene '" + scene.name + "': " + e.what());
  }
  return o.placements;
}

std::vector<Case> casesOf(const std::vector<Scene>& scenes, const PlanningWorld& world,
                          const Options& o) {
  if (!o.objects.empty()) hfts::bench::requireKnown(o.objects, world.objectNames(), "object");
  std::vector<Case> cases;
  for (const Scene& scene : scenes)
    for (const std::string& placement : placementsOf(scene, o))
      for (const std::string& object : objectsFor(scene, world, o)) {
        if (world.object(object) == nullptr)
          throw std::runtime_error("scene '" + scene.name + "' targets '" + object +
                                   "', which has no database in --db (build it with "
                                   "hfts-preprocess, or choose --objects)");
        cases.push_back({scene.withPlacement(placement), object, placement});
      }
  return cases;
}

/// The planner parameters the algorithms set must exist (values are
/// checked by the first run).
void checkParameterNames(const std::vector<Algorithm>& algorithms, const PlanningWorld& world) {
  std::vector<std::string> declared;
  for (const auto& p : hfts::planner::plannerParameters(world)) declared.push_back(p.name);
  for (const Algorithm& a : algorithms)
    for (const auto& setting : a.parameters)
      if (std::find(declared.begin(), declared.end(), setting.first) == declared.end())
        throw UsageError("algorithm '" + a.name + "': unknown planner parameter '" + setting.first +
                         "' (see docs/planning.md#parameters)");
}

/// Moves a case whose object cannot be held to e.unholdable, saying why.
void leaveOut(Experiment& e, const Case& c, const std::string& reason) {
  e.unholdable.push_back(c);
  std::cerr << "hfts-bench: left out " << c.scene.name << "/" << c.object
            << (c.placement == "target" ? "" : " at " + c.placement) << ": " << reason << "\n";
}

/// --holdable-from: the cases the file answers holdable stay, the others
/// move to e.unholdable; a case the file does not answer is an error
/// before any run.
void sortOutHoldableFromFile(Experiment& e, const hfts::bench::HoldabilityFile& answers,
                             const Options& o) {
  std::vector<Case> holdable;
  for (const Case& c : e.cases) {
    if (answers.holdable({c.scene.name, c.object, c.placement}))
      holdable.push_back(c);
    else
      leaveOut(e, c, "not holdable in " + o.holdableFrom);
  }
  e.cases = std::move(holdable);
}

/// holdability() for every case (the robot's default parameters, seed 1);
/// with --holdable-only, the cases whose object cannot be held move to
/// e.unholdable. With --holdability, writes the answers.
void sortOutHoldable(Experiment& e, const Options& o) {
  std::vector<hfts::bench::HoldabilityRecord> records;
  std::vector<Case> holdable;
  for (const Case& c : e.cases) {
    hfts::planner::PlanRequest request;
    request.scene = c.scene;
    request.object = c.object;
    const auto began = std::chrono::steady_clock::now();
    hfts::bench::HoldabilityRecord r{{c.scene.name, c.object, c.placement},
                                     hfts::bench::holdability(*e.world, request)};
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
    if (r.answer.holdable || !o.holdableOnly)
      holdable.push_back(c);
    else
      leaveOut(e, c, r.answer.reason);
    records.push_back(std::move(r));
  }
  if (!o.holdability.empty()) hfts::bench::writeHoldabilityCsv(o.holdability, records);
  e.cases = std::move(holdable);
}

Experiment prepare(const Options& o) {
  Experiment e;
  e.physics = !o.noPhysics;
  e.algorithms = hfts::bench::parseAlgorithms(o.algorithms);
  hfts::bench::checkRunsAndTimeLimit(o.runs, o.timeLimit);
  const std::vector<Scene> scenes = loadScenes(o);
  std::optional<hfts::bench::HoldabilityFile> answers;  // read before the slow loadWorld
  if (!o.holdableFrom.empty()) answers.emplace(o.holdableFrom);
  e.world = loadWorld(o);
  checkParameterNames(e.algorithms, *e.world);
  e.cases = casesOf(scenes, *e.world, o);
  if (answers)
    sortOutHoldableFromFile(e, *answers, o);
  else if (o.holdableOnly || !o.holdability.empty())
    sortOutHoldable(e, o);
  e.runs = o.runs;
  e.firstSeed = o.firstSeed;
  e.timeLimit = o.timeLimit;
  e.csv = o.out;
  e.outDir = o.outDir;
  return e;
}

double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

RunRecord runOnce(const Experiment& e, const Case& c, const Algorithm& algorithm, int seed) {
  hfts::planner::PlanRequest request;
  request.scene = c.scene;
  request.object = c.object;
  request.algorithm = algorithm.algorithm;
  request.iterations = algorithm.iterations;
  request.parameters = algorithm.parameters;
  request.preset = algorithm.preset;
  // The paper's planner ends with the hand closed; the others lift.
  if (algorithm.preset == hfts::planner::PlannerPreset::kPaper) request.lift.reset();
  if (algorithm.lift) {
    request.lift = *algorithm.lift > 0.0
                       ? std::optional(hfts::planner::LiftOptions{*algorithm.lift})
                       : std::nullopt;
  }
  request.seed = static_cast<std::uint64_t>(seed);
  request.time_limit = e.timeLimit;
  request.validate = e.physics;
  const double cpu = processCpuSeconds();
  const auto result = hfts::planner::planGrasp(*e.world, request);
  return hfts::bench::makeRunRecord({c.scene.name, c.object, c.placement}, algorithm.name,
                                    request.seed, result, processCpuSeconds() - cpu);
}

std::vector<std::string> namesOf(const std::vector<Algorithm>& algorithms) {
  std::vector<std::string> names;
  for (const Algorithm& a : algorithms) names.push_back(a.name);
  return names;
}

/// The OMPL benchmark log of one case (experiment mode).
void writeLog(const Experiment& e, const Case& c, const std::vector<RunRecord>& records,
              std::chrono::system_clock::time_point started, const std::string& commandLine) {
  hfts::bench::LogExperiment log;
  log.scene = c.scene.name;
  log.object = c.object;
  log.time_limit = e.timeLimit;
  log.runs = e.runs;
  log.started = started;
  log.seconds = std::chrono::duration<double>(std::chrono::system_clock::now() - started).count();
  log.setup =
      "hfts-bench: integrated grasp and motion planning (HFTS, ICRA 2017)\n"
      "scene " +
      c.scene.name + ", object " + c.object + " at placement '" + c.placement + "'\n" +
      "one planGrasp call per run, seeds " + std::to_string(e.firstSeed) + ".." +
      std::to_string(e.firstSeed + e.runs - 1) + "; rrtconnect samples goals in a second thread\n" +
      "command: " + commandLine + "\n";
  fs::create_directories(e.outDir / "ompl");
  const std::string at = c.placement == "target" ? "" : "_" + c.placement;
  hfts::bench::writeOmplBenchmarkLog(
      e.outDir / "ompl" / (c.scene.name + "_" + c.object + at + ".log"), log, records,
      namesOf(e.algorithms));
}

std::size_t runCount(const Experiment& e) {
  return e.cases.size() * e.algorithms.size() * static_cast<std::size_t>(e.runs);
}

std::vector<RunRecord> runAll(const Experiment& e, const std::string& commandLine) {
  std::vector<RunRecord> records;
  hfts::bench::writeCsvAtomically(e.csv, records);  // an unwritable --out fails before any run
  hfts::bench::Progress progress(std::cerr, ::isatty(STDERR_FILENO) != 0, runCount(e));
  for (const Case& c : e.cases) {
    const auto started = std::chrono::system_clock::now();
    for (const Algorithm& algorithm : e.algorithms)
      for (int seed = e.firstSeed; seed < e.firstSeed + e.runs; ++seed) {
        records.push_back(runOnce(e, c, algorithm, seed));
        hfts::bench::writeCsvAtomically(e.csv, records);
        progress.done(records.back());
      }
    if (!e.outDir.empty()) writeLog(e, c, records, started, commandLine);
  }
  return records;
}

int plot(const Experiment& e, const Options& o) {
  const fs::path script = hfts::bench::resolveDefault("", "bench/plot_results.py");
  std::ostringstream limit;
  limit << e.timeLimit;
  const int status = hfts::bench::runPython(
      o.python, script,
      {e.csv.string(), "--out-dir", e.outDir.string(), "--time-limit", limit.str()});
  if (status != 0) {
    std::cerr << "hfts-bench: the plots failed (" << o.python << " " << script.string()
              << " exited with " << status << "); the CSV and the logs are complete\n";
    return 1;
  }
  std::cout << "plots and summary.md written to " << e.outDir.string() << "\n";
  return 0;
}

int benchmark(const Options& o) {
  const Experiment e = prepare(o);
  if (!e.outDir.empty()) {
    fs::create_directories(e.outDir);
    std::cerr << "hfts-bench: " << runCount(e) << " runs, at most " << std::fixed
              << std::setprecision(1) << static_cast<double>(runCount(e)) * e.timeLimit / 60.0
              << " minutes if every run hits the time limit\n";
  }
  if (!e.unholdable.empty())
    std::cerr << "hfts-bench: " << e.unholdable.size() << " of "
              << e.unholdable.size() + e.cases.size() << " cases left out as not holdable\n";
  const std::vector<RunRecord> records = runAll(e, o.commandLine);
  hfts::bench::printSummary(std::cout, records, namesOf(e.algorithms));
  std::cout << records.size() << " runs written to " << e.csv.string() << "\n";
  if (e.outDir.empty() || o.noPlots) return 0;
  return plot(e, o);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Benchmarks integrated grasp and motion planning (coupled) against the decoupled\n"
      "baseline and OMPL's RRTConnect on the bundled scenes, as in the paper's experiments.\n"
      "  hfts-bench --scenes table,shelf --algorithms coupled,decoupled20 --runs 10 "
      "--out results.csv\n"
      "  hfts-bench --experiment paper --out-dir results   # CSV, OMPL logs, plots\n"
      "  hfts-bench --mbm problems --out mbm.csv           # MotionBenchMaker\n"
      "  hfts-bench --place objects/pick_and_place/tasks.json --out place.csv  # pick and place",
      "hfts-bench"};
  Options options;
  const Given given = addOptions(app, options);
  for (int i = 0; i < argc; ++i) options.commandLine += (i > 0 ? " " : "") + std::string(argv[i]);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // --help exits 0, every usage error 2
  }
  try {
    if (!options.mbm.empty()) return benchmarkMbm(options, given);
    if (!options.place.empty()) return benchmarkPlace(options, given);
    applyDesign(options, given);
    return benchmark(options);
  } catch (const UsageError& e) {
    std::cerr << "hfts-bench: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "hfts-bench: " << e.what() << "\n";
    return 1;
  }
}
