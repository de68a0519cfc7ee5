// Speed of the offline stage (figures in docs/performance.md):
//   build/bin/preprocess_benchmark --benchmark_min_time=1
// The pipeline is single-threaded (Embree runs with one thread), so every
// figure is for one core.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>

#include "hfts_db/object_database.h"
#include "preprocess/database_builder.h"

namespace {

using hfts::TriangleMesh;

/// A torus (R 6 cm, r 2 cm) with 2 * nu * nv triangles.
TriangleMesh torus(int nu, int nv) {
  TriangleMesh mesh;
  mesh.vertices.resize(nu * nv, 3);
  mesh.triangles.resize(2 * nu * nv, 3);
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nv;
      mesh.vertices.row(i * nv + j) << (0.06 + 0.02 * std::cos(v)) * std::cos(u),
          (0.06 + 0.02 * std::cos(v)) * std::sin(u), 0.02 * std::sin(v);
      const auto a = static_cast<std::uint32_t>(i * nv + j);
      const auto b = static_cast<std::uint32_t>(((i + 1) % nu) * nv + j);
      const auto c = static_cast<std::uint32_t>(((i + 1) % nu) * nv + (j + 1) % nv);
      const auto d = static_cast<std::uint32_t>(i * nv + (j + 1) % nv);
      mesh.triangles.row(2 * (i * nv + j)) << a, b, c;
      mesh.triangles.row(2 * (i * nv + j) + 1) << a, c, d;
    }
  }
  return mesh;
}

void BM_Build100kTriangleMesh(benchmark::State& state) {
  const TriangleMesh mesh = torus(250, 200);
  for (auto _ : state) {
    const auto result = hfts::preprocess::buildObjectDatabase(mesh, true, {}, "torus-100k");
    benchmark::DoNotOptimize(result.database.positions.data());
    state.counters["contacts"] = static_cast<double>(result.database.numContacts());
  }
  state.counters["triangles"] = static_cast<double>(mesh.triangles.rows());
}
BENCHMARK(BM_Build100kTriangleMesh)->Unit(benchmark::kMillisecond)->UseRealTime();

const std::filesystem::path kMeshes = std::filesystem::path(HFTS_SOURCE_DIR) / "objects" / "meshes";

void BM_BuildBundledObject(benchmark::State& state, const std::string& file) {
  for (auto _ : state) {
    const auto result = hfts::preprocess::buildObjectDatabaseFromFile(kMeshes / file, {});
    benchmark::DoNotOptimize(result.database.positions.data());
    state.counters["contacts"] = static_cast<double>(result.database.numContacts());
  }
}

void BM_LoadDatabase(benchmark::State& state, const std::string& file) {
  const auto path = std::filesystem::temp_directory_path() / ("hfts-bench-" + file + ".h5");
  hfts::db::saveObjectDatabase(
      hfts::preprocess::buildObjectDatabaseFromFile(kMeshes / file, {}).database, path);
  for (auto _ : state) {
    const auto db = hfts::db::loadObjectDatabase(path);
    benchmark::DoNotOptimize(db.positions.data());
  }
  state.counters["bytes"] = static_cast<double>(std::filesystem::file_size(path));
  std::filesystem::remove(path);
}

void registerBundled() {
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(kMeshes))
    files.push_back(entry.path().filename().string());
  std::sort(files.begin(), files.end());
  for (const std::string& file : files) {
    benchmark::RegisterBenchmark(("BM_BuildBundledObject/" + file).c_str(), BM_BuildBundledObject,
                                 file)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
    benchmark::RegisterBenchmark(("BM_LoadDatabase/" + file).c_str(), BM_LoadDatabase, file)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
}

}  // namespace

int main(int argc, char** argv) {
  registerBundled();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
