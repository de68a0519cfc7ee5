// Speed of the physics check, simulateGrasp with its seven trials (figures
// in docs/performance.md#physics):
//   build/bin/physics_benchmark --benchmark_min_time=1
// The grasps are the planner's: planGrasp (coupled, seed 1) in the bundled
// table scene for each bundled robot, its path's last two configurations
// as pre-grasp and grasp; planning happens before the timing. Each case's
// verdict is in its counters (held_fraction) and label (the nominal
// trial's failure, if any).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>

#include "grasp/hand_map_builder.h"
#include "physics/simulate_grasp.h"
#include "planner/grasp_motion_planner.h"
#include "planner/planning_world.h"
#include "preprocess/database_builder.h"

namespace {

using namespace hfts;

const std::filesystem::path kSource = HFTS_SOURCE_DIR;

/// One planned grasp to simulate.
struct Case {
  std::shared_ptr<const planner::PlanningWorld> world;
  robot::Scene scene;  ///< the object where the plan had it
  std::string object;
  Eigen::VectorXd pregrasp, grasp;
};

/// The bundled mesh of `object`, whatever its format.
std::filesystem::path meshFile(const std::string& object) {
  for (const auto& entry : std::filesystem::directory_iterator(kSource / "objects/meshes"))
    if (entry.path().stem() == object) return entry.path();
  throw std::runtime_error("no bundled mesh '" + object + "'");
}

std::shared_ptr<const planner::PlanningWorld> world(const std::string& robotName,
                                                    const std::string& object) {
  const robot::RobotModel model =
      robot::RobotModel::load(kSource / "robots" / robotName / (robotName + ".json"));
  db::HandMap map = grasp::buildHandMap(model);
  std::map<std::string, db::ObjectDatabase> objects;
  objects.emplace(object, preprocess::buildObjectDatabaseFromFile(meshFile(object), {}).database);
  return std::make_shared<planner::PlanningWorld>(model, std::move(map), std::move(objects));
}

/// Plans `object` in the table scene for `robotName`; nullopt when no plan.
std::optional<Case> plannedCase(const std::string& robotName, const std::string& object) {
  Case c;
  c.world = world(robotName, object);
  planner::PlanRequest request;
  request.scene = robot::loadScene(kSource / "objects/scenes/table.json");
  request.object = object;
  request.time_limit = 30.0;
  const planner::PlanResult result = planner::planGrasp(*c.world, request);
  if (!result.success || result.path.size() < 2) return std::nullopt;
  c.scene = request.scene;
  c.scene.target_object = object;
  c.scene.target_pose = result.object_pose;
  c.object = object;
  c.pregrasp = result.path[result.path.size() - 2];
  c.grasp = result.path.back();
  return c;
}

void BM_SimulateGrasp(benchmark::State& state, const std::string& robotName,
                      const std::string& object) {
  const std::optional<Case> c = plannedCase(robotName, object);
  if (!c) {
    state.SkipWithError("no plan");
    return;
  }
  physics::GraspVerdict verdict;
  for (auto _ : state) {
    verdict = physics::simulateGrasp(c->world->collisionModel(), c->scene,
                                     *c->world->object(object), c->pregrasp, c->grasp);
    benchmark::DoNotOptimize(verdict.held);
  }
  state.counters["held_fraction"] = verdict.held_fraction;
  state.counters["mass_g"] = verdict.mass * 1000;
  state.SetLabel(verdict.lift_direction + (verdict.trials[0].failure.empty()
                                               ? std::string(", nominal held")
                                               : ", nominal: " + verdict.trials[0].failure));
}

/// One benchmark per robot and object, each simulated once (seconds each).
const bool registered = [] {
  const std::pair<const char*, const char*> robots[] = {
      {"panda", "panda_gripper"}, {"kr5", "kr5_sdh"}, {"ur5e", "ur5e_allegro"}};
  for (const auto& [shortName, robotName] : robots)
    for (const char* object : {"box", "bottle", "mug", "bowl"})
      benchmark::RegisterBenchmark(
          (std::string("BM_SimulateGrasp/") + shortName + "_" + object).c_str(),
          [robotName = std::string(robotName), object = std::string(object)](
              benchmark::State& state) { BM_SimulateGrasp(state, robotName, object); })
          ->Unit(benchmark::kSecond)
          ->Iterations(1);
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
