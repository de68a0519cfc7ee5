// The Python module's batch calls timed without Python: the same C++
// functions (python/src/batch.h) on the same inputs, which
// python/bench/batch_overhead.py writes and then times through the module,
// side by side (docs/performance.md, "Python batch calls").
//   build/bin/python_batch_benchmark --inputs DIR [Google Benchmark flags]
// DIR holds inputs.json (robot config, database folder, scene, counts) and
// the arrays as raw little-endian float64: quality_positions.f64 and
// quality_normals.f64 (N x 3 x 3), ik_poses.f64 (N x 4 x 4, palm poses in
// the base frame), configurations.f64 (N x DoF).
#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "batch.h"
#include "planner/planning_world.h"
#include "robot/scene.h"

namespace {

using namespace hfts;

struct Inputs {
  nlohmann::json meta;
  std::vector<double> positions, normals, poses, configurations;
  std::shared_ptr<const planner::PlanningWorld> world;
  robot::Scene scene;
};

Inputs& inputs() {
  static Inputs in;
  return in;
}

std::vector<double> readDoubles(const std::filesystem::path& path, std::size_t count) {
  std::ifstream file(path, std::ios::binary);
  std::vector<double> values(count);
  file.read(reinterpret_cast<char*>(values.data()), static_cast<std::streamsize>(count * 8));
  if (!file)
    throw std::runtime_error("cannot read " + std::to_string(count) + " doubles from " +
                             path.string());
  return values;
}

void load(const std::filesystem::path& dir) {
  Inputs& in = inputs();
  std::ifstream metaFile(dir / "inputs.json");
  in.meta = nlohmann::json::parse(metaFile);
  const auto grasps = in.meta.at("grasps").get<std::size_t>();
  const auto poses = in.meta.at("poses").get<std::size_t>();
  const auto configurations = in.meta.at("configurations").get<std::size_t>();
  in.positions = readDoubles(dir / "quality_positions.f64", grasps * 9);
  in.normals = readDoubles(dir / "quality_normals.f64", grasps * 9);
  in.poses = readDoubles(dir / "ik_poses.f64", poses * 16);
  in.world = planner::PlanningWorld::load(in.meta.at("robot").get<std::string>(),
                                          in.meta.at("db").get<std::string>());
  in.configurations =
      readDoubles(dir / "configurations.f64",
                  configurations * static_cast<std::size_t>(in.world->robot().numDofs()));
  in.scene = robot::loadScene(in.meta.at("scene").get<std::string>());
}

void BM_GraspQualityBatch(benchmark::State& state) {
  const Inputs& in = inputs();
  grasp::GraspQualityRequest common;
  const auto& center = in.meta.at("center");
  common.center = Eigen::Vector3d(center[0], center[1], center[2]);
  common.torque_scale = in.meta.at("torque_scale");
  common.direction = grasp::NormalDirection::kOutward;
  const std::size_t grasps = in.positions.size() / 9;
  std::vector<double> epsilons(grasps);
  for (auto _ : state) {
    python::graspQualities(in.positions.data(), in.normals.data(), grasps, 3, common,
                           epsilons.data());
    benchmark::DoNotOptimize(epsilons.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * grasps));
}

void BM_ArmIkBatch(benchmark::State& state) {
  const Inputs& in = inputs();
  const std::size_t poses = in.poses.size() / 16;
  for (auto _ : state) {
    python::IkSolutions found = python::armIkBatch(in.world->ik(), in.poses.data(), poses, true, 1);
    benchmark::DoNotOptimize(found.configurations.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * poses));
}

void BM_CollisionBatch(benchmark::State& state) {
  const Inputs& in = inputs();
  robot::Scene scene = in.scene;
  const db::ObjectDatabase* target = in.world->object(scene.target_object);
  if (target == nullptr) throw std::runtime_error("no database of " + scene.target_object);
  scene.target_pose = robot::targetPose(scene, target->geometry.mesh_vertices);
  robot::CollisionChecker checker(in.world->collisionModel(), scene, &target->geometry,
                                  in.world->collisionMesh(scene.target_object),
                                  in.world->surface(scene.target_object));
  const int dofs = in.world->robot().numDofs();
  const std::size_t count = in.configurations.size() / static_cast<std::size_t>(dofs);
  std::unique_ptr<bool[]> colliding(new bool[count]);
  for (auto _ : state) {
    benchmark::DoNotOptimize(python::collisionBatch(checker, in.configurations.data(), count, dofs,
                                                    robot::CollisionRequest{}, colliding.get()));
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * count));
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir;
  std::vector<char*> rest;
  for (int i = 0; i < argc; ++i) {
    if (std::strncmp(argv[i], "--inputs=", 9) == 0) {
      dir = argv[i] + 9;
    } else {
      rest.push_back(argv[i]);
    }
  }
  if (dir.empty()) {
    std::cerr << "usage: python_batch_benchmark --inputs=DIR [benchmark flags] (DIR: written by "
                 "python/bench/batch_overhead.py)\n";
    return 2;
  }
  try {
    load(dir);
  } catch (const std::exception& e) {
    std::cerr << "python_batch_benchmark: " << e.what() << "\n";
    return 1;
  }
  benchmark::RegisterBenchmark("BM_GraspQualityBatch", BM_GraspQualityBatch)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_ArmIkBatch", BM_ArmIkBatch)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_CollisionBatch", BM_CollisionBatch)
      ->Unit(benchmark::kMillisecond);
  int count = static_cast<int>(rest.size());
  benchmark::Initialize(&count, rest.data());
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
