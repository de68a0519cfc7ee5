// hfts-bench: the paper's experiments (Sec. V). Plans every combination of
// scene, object, algorithm and seed, writes one CSV row per run and prints
// a per-algorithm summary. See docs/benchmarks.md.
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "bench_options.h"
#include "bench_report.h"
#include "planner/grasp_motion_planner.h"
#include "planner/scene.h"
#include "run_record.h"

namespace {

namespace fs = std::filesystem;
using hfts::bench::Algorithm;
using hfts::bench::RunRecord;
using hfts::bench::UsageError;
using hfts::planner::PlanningWorld;
using hfts::planner::Scene;

struct Options {
  std::string db, robot, sceneDir, out;
  std::vector<std::string> scenes, objects,
      algorithms{"coupled", "decoupled20", "decoupled60", "decoupled100"};
  int runs = 10;
  double timeLimit = 60.0;
};

/// Everything the runs need, checked: a bad argument never costs a run.
struct Experiment {
  std::vector<Algorithm> algorithms;
  std::vector<Scene> scenes;
  std::vector<std::string> objects;  ///< empty: each scene's target object
  std::shared_ptr<const PlanningWorld> world;
};

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--db", o.db, "Object databases and hand map (default build/databases)")
      ->type_name("DIR");
  app.add_option("--robot", o.robot, "Robot config (default robots/kr5_sdh/kr5_sdh.json)")
      ->type_name("CONFIG");
  app.add_option("--scene-dir", o.sceneDir, "Where scene S is S.json (default objects/scenes)")
      ->type_name("DIR");
  app.add_option("--scenes", o.scenes, "Scenes to plan in (default: every scene in --scene-dir)")
      ->delimiter(',');
  app.add_option("--objects", o.objects,
                 "Objects placed at each scene's target pose (default: each scene's target)")
      ->delimiter(',');
  app.add_option("--algorithms", o.algorithms, "coupled and/or decoupledN (N iterations/level)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--runs", o.runs, "Runs per combination, with seeds 1..N")->capture_default_str();
  app.add_option("--time-limit", o.timeLimit, "Seconds per run")->capture_default_str();
  app.add_option("--out", o.out, "CSV file, one row per run (rewritten after each run)")
      ->required()
      ->type_name("FILE");
}

std::vector<Scene> loadScenes(const Options& o) {
  const fs::path dir = hfts::bench::resolveDefault(o.sceneDir, "objects/scenes");
  const std::vector<std::string> available = hfts::bench::sceneNamesIn(dir);
  if (available.empty()) throw std::runtime_error("no *.json scene in '" + dir.string() + "'");
  hfts::bench::requireKnown(o.scenes, available, "scene");
  std::vector<Scene> scenes;
  for (const std::string& name : o.scenes.empty() ? available : o.scenes) {
    scenes.push_back(hfts::planner::loadScene(dir / (name + ".json")));
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

void checkObjects(const Experiment& e, const Options& o) {
  if (!o.objects.empty()) {
    hfts::bench::requireKnown(o.objects, e.world->objectNames(), "object");
    return;
  }
  for (const Scene& scene : e.scenes)
    if (e.world->object(scene.target_object) == nullptr)
      throw std::runtime_error("scene '" + scene.name + "' targets '" + scene.target_object +
                               "', which has no database in --db (build it with "
                               "hfts-preprocess, or choose --objects)");
}

Experiment prepare(const Options& o) {
  Experiment e;
  e.algorithms = hfts::bench::parseAlgorithms(o.algorithms);
  hfts::bench::checkRunsAndTimeLimit(o.runs, o.timeLimit);
  e.scenes = loadScenes(o);
  e.world = loadWorld(o);
  e.objects = o.objects;
  checkObjects(e, o);
  return e;
}

RunRecord runOnce(const Experiment& e, const Scene& scene, const std::string& object,
                  const Algorithm& algorithm, int seed, double timeLimit) {
  hfts::planner::PlanRequest request;
  request.scene = scene;
  request.object = object;
  request.algorithm = algorithm.algorithm;
  request.iterations = algorithm.iterations;
  request.seed = static_cast<std::uint64_t>(seed);
  request.time_limit = timeLimit;
  const auto result = hfts::planner::planGrasp(*e.world, request);
  return hfts::bench::makeRunRecord(scene.name, object, algorithm.name, request.seed, result);
}

std::vector<RunRecord> runAll(const Experiment& e, const Options& o) {
  std::vector<RunRecord> records;
  hfts::bench::writeCsvAtomically(o.out, records);  // an unwritable --out fails before any run
  const std::size_t perScene = e.objects.empty() ? 1 : e.objects.size();
  hfts::bench::Progress progress(
      std::cerr, ::isatty(STDERR_FILENO) != 0,
      e.scenes.size() * perScene * e.algorithms.size() * static_cast<std::size_t>(o.runs));
  for (const Scene& scene : e.scenes)
    for (const std::string& object :
         e.objects.empty() ? std::vector<std::string>{scene.target_object} : e.objects)
      for (const Algorithm& algorithm : e.algorithms)
        for (int seed = 1; seed <= o.runs; ++seed) {
          records.push_back(runOnce(e, scene, object, algorithm, seed, o.timeLimit));
          hfts::bench::writeCsvAtomically(o.out, records);
          progress.done(records.back());
        }
  return records;
}

int benchmark(const Options& o) {
  const Experiment e = prepare(o);
  const std::vector<RunRecord> records = runAll(e, o);
  std::vector<std::string> names;
  for (const Algorithm& a : e.algorithms) names.push_back(a.name);
  hfts::bench::printSummary(std::cout, records, names);
  std::cout << records.size() << " runs written to " << o.out << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Benchmarks integrated grasp and motion planning (coupled) against the decoupled\n"
      "baseline on the bundled scenes, as in the paper's experiments.\n"
      "  hfts-bench --scenes table,shelf --algorithms coupled,decoupled20 --runs 10 "
      "--out results.csv",
      "hfts-bench"};
  Options options;
  addOptions(app, options);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // --help exits 0, every usage error 2
  }
  try {
    return benchmark(options);
  } catch (const UsageError& e) {
    std::cerr << "hfts-bench: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "hfts-bench: " << e.what() << "\n";
    return 1;
  }
}
