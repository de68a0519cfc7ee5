// Speed of the hand reachability map (figures in docs/hand_reachability.md):
//   build/bin/hand_reachability_benchmark --benchmark_min_time=1
// One query is one contact triple, every assignment of contacts to fingers
// included, single-threaded.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <vector>

#include "grasp/hand_reachability.h"
#include "robot/kinematics.h"

namespace {

using hfts::grasp::HandQueryOptions;
using hfts::grasp::HandReachability;
using hfts::robot::RobotModel;

const RobotModel& kr5() {
  static const RobotModel model =
      RobotModel::load(std::filesystem::path(HFTS_SOURCE_DIR) / "robots/kr5_sdh/kr5_sdh.json");
  return model;
}

const hfts::db::HandMap& defaultMap() {
  static const hfts::db::HandMap map = hfts::grasp::buildHandMap(kr5());
  return map;
}

struct Triple {
  Eigen::Matrix3Xd contacts = Eigen::Matrix3Xd(3, 3);
  Eigen::Matrix3Xd outward = Eigen::Matrix3Xd(3, 3);
};

Eigen::Vector3d randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
}

/// Triples the hand reaches exactly: fingertips of random grasp postures
/// (palm frame), contacts in shuffled order.
std::vector<Triple> reachableTriples(std::size_t count) {
  std::mt19937_64 rng(5);
  const int arm = kr5().numArmDofs(), dofs = kr5().numHandDofs();
  std::vector<Triple> out;
  while (out.size() < count) {
    Eigen::VectorXd q = kr5().home();
    for (int d = arm; d < arm + dofs; ++d)
      q(d) = std::uniform_real_distribution<double>(kr5().lowerLimits()(d),
                                                    kr5().upperLimits()(d))(rng);
    const auto frames =
        hfts::robot::fingertipFrames(kr5(), hfts::robot::forwardKinematics(kr5(), q));
    const Eigen::Isometry3d palm =
        hfts::robot::forwardKinematics(kr5(), q)[static_cast<std::size_t>(kr5().palmLink())];
    Triple t;
    t.contacts = palm.inverse() * frames.positions;
    t.outward = -(palm.linear().transpose() * frames.normals);
    if (!hfts::grasp::isGraspPosture(t.contacts, -t.outward, {})) continue;
    t.contacts.col(0).swap(t.contacts.col(2));
    t.outward.col(0).swap(t.outward.col(2));
    out.push_back(t);
  }
  return out;
}

/// What the grasp optimiser asks about: three random points on a sphere of
/// radius 3 to 8 cm with their outward normals. Most are not reachable
/// exactly, so the refinement runs until it stalls.
std::vector<Triple> objectTriples(std::size_t count) {
  std::mt19937_64 rng(6);
  std::vector<Triple> out(count);
  for (Triple& t : out) {
    const double radius = std::uniform_real_distribution<double>(0.03, 0.08)(rng);
    for (int c = 0; c < 3; ++c) {
      t.outward.col(c) = randomUnit(rng);
      t.contacts.col(c) = radius * t.outward.col(c);
    }
  }
  return out;
}

void runQueries(benchmark::State& state, const std::vector<Triple>& triples,
                const HandQueryOptions& options) {
  const HandReachability reachability(kr5(), defaultMap(), options);
  std::size_t i = 0;
  double reached = 0;
  for (auto _ : state) {
    const Triple& t = triples[i++ % triples.size()];
    const auto answer = reachability.query(t.contacts, t.outward);
    benchmark::DoNotOptimize(answer.residual);
    reached += answer.residual < 1e-3 ? 1 : 0;
  }
  state.counters["reached"] = reached / static_cast<double>(state.iterations());
}

void BM_QueryReachableTriple(benchmark::State& state) {
  static const std::vector<Triple> triples = reachableTriples(1000);
  runQueries(state, triples, {});
}
BENCHMARK(BM_QueryReachableTriple)->Unit(benchmark::kMicrosecond);

void BM_QueryObjectTriple(benchmark::State& state) {
  static const std::vector<Triple> triples = objectTriples(1000);
  runQueries(state, triples, {});
}
BENCHMARK(BM_QueryObjectTriple)->Unit(benchmark::kMicrosecond);

void BM_QueryReachableTripleThorough(benchmark::State& state) {
  static const std::vector<Triple> triples = reachableTriples(1000);
  runQueries(state, triples, HandQueryOptions::thorough());
}
BENCHMARK(BM_QueryReachableTripleThorough)->Unit(benchmark::kMicrosecond);

void BM_QueryObjectTripleThorough(benchmark::State& state) {
  static const std::vector<Triple> triples = objectTriples(1000);
  runQueries(state, triples, HandQueryOptions::thorough());
}
BENCHMARK(BM_QueryObjectTripleThorough)->Unit(benchmark::kMicrosecond);

/// SAMPLENULLSPACE's question: every hand posture that takes a reachable
/// triple (fingertips within 5 mm), thorough() search; "postures" counts
/// them per triple.
void BM_QueryAlternativesThorough(benchmark::State& state) {
  static const std::vector<Triple> triples = reachableTriples(1000);
  const HandReachability reachability(kr5(), defaultMap(), HandQueryOptions::thorough());
  std::size_t i = 0;
  double postures = 0;
  for (auto _ : state) {
    const Triple& t = triples[i++ % triples.size()];
    const auto answers = reachability.queryAlternatives(t.contacts, t.outward, 0.005);
    benchmark::DoNotOptimize(answers.data());
    postures += static_cast<double>(answers.size());
  }
  state.counters["postures"] = postures / static_cast<double>(state.iterations());
}
BENCHMARK(BM_QueryAlternativesThorough)->Unit(benchmark::kMicrosecond);

/// The best aligned map sample only, no refinement: the floor of the query.
void BM_QueryMapOnly(benchmark::State& state) {
  static const std::vector<Triple> triples = objectTriples(1000);
  runQueries(state, triples, {8, 4.0, 1, 0, 0, 1, 0});
}
BENCHMARK(BM_QueryMapOnly)->Unit(benchmark::kMicrosecond);

void BM_BuildMap(benchmark::State& state) {
  for (auto _ : state) {
    const auto map = hfts::grasp::buildHandMap(kr5());
    benchmark::DoNotOptimize(map.configurations.data());
    state.counters["samples"] = static_cast<double>(map.numSamples());
    state.counters["draws"] = static_cast<double>(map.num_draws);
  }
}
BENCHMARK(BM_BuildMap)->Unit(benchmark::kMillisecond);

void BM_LoadMap(benchmark::State& state) {
  const auto path = std::filesystem::temp_directory_path() / "hfts-bench-hand-map.h5";
  hfts::db::saveHandMap(defaultMap(), path);
  for (auto _ : state) {
    const auto map = hfts::db::loadHandMap(path);
    benchmark::DoNotOptimize(map.configurations.data());
  }
  state.counters["file_bytes"] = static_cast<double>(std::filesystem::file_size(path));
  std::filesystem::remove(path);
}
BENCHMARK(BM_LoadMap)->Unit(benchmark::kMillisecond);

void BM_ConstructReachability(benchmark::State& state) {
  for (auto _ : state) {
    const HandReachability reachability(kr5(), defaultMap());
    benchmark::DoNotOptimize(&reachability);
  }
}
BENCHMARK(BM_ConstructReachability)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
