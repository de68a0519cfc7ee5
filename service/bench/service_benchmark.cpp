// Speed of the planning service (figures in docs/performance.md):
//   build/bin/service_benchmark
// An in-process hfts-server (loopback TCP, no request log) serves the bin
// and table scenes with the blob and mug databases, built at start-up; the
// C++ client library (hfts::client::RpcClient) makes the calls.
#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include <array>
#include <filesystem>
#include <thread>

#include "client/rpc_client.h"
#include "grasp/hand_reachability.h"
#include "preprocess/database_builder.h"
#include "service/plan_request_json.h"
#include "service/server.h"

namespace {

using namespace hfts;
using nlohmann::json;

const std::filesystem::path kSource = HFTS_SOURCE_DIR;
constexpr int kWorkers = 2;

std::shared_ptr<const service::PlanningCatalog> makeCatalog() {
  std::map<std::string, db::ObjectDatabase> objects;
  for (const char* mesh : {"blob.stl", "mug.ply"}) {
    auto d = preprocess::buildObjectDatabaseFromFile(kSource / "objects/meshes" / mesh, {});
    objects.emplace(d.database.name, std::move(d.database));
  }
  auto robot = robot::RobotModel::load(kSource / "robots/kr5_sdh/kr5_sdh.json");
  auto map = grasp::buildHandMap(robot);
  std::map<std::string, robot::Scene> scenes;
  for (const char* name : {"bin", "table"}) {
    scenes.emplace(name,
                   robot::loadScene(kSource / "objects/scenes" / (name + std::string(".json"))));
    scenes.at(name).name = name;
  }
  return std::make_shared<const service::PlanningCatalog>(
      std::make_shared<const planner::PlanningWorld>(std::move(robot), std::move(map),
                                                     std::move(objects)),
      std::move(scenes), kSource / "objects/scenes");
}

/// The server, running on its own thread for the whole program.
class BenchServer {
 public:
  BenchServer()
      : catalog_(makeCatalog()), server_(options(), catalog_), thread_([this] { server_.run(); }) {}
  ~BenchServer() {
    server_.stop();
    thread_.join();
  }
  std::uint16_t port() const { return server_.port(); }
  const service::PlanningCatalog& catalog() const { return *catalog_; }

 private:
  static service::ServerOptions options() {
    service::ServerOptions o;
    o.workers = kWorkers;
    o.handle_signals = false;
    o.queue_capacity = 256;
    return o;
  }
  std::shared_ptr<const service::PlanningCatalog> catalog_;
  service::Server server_;
  std::thread thread_;
};

BenchServer& server() {
  static BenchServer s;
  return s;
}

const json kQuality = json::parse(R"({"contacts": [
  {"position": [1, 0, 0], "normal": [-1, 0, 0]},
  {"position": [-0.5, 0.8660254037844386, 0], "normal": [0.5, -0.8660254037844386, 0]},
  {"position": [-0.5, -0.8660254037844386, 0], "normal": [0.5, 0.8660254037844386, 0]}]})");

/// The plan requests of one pass: the bin and table scenes, seeds 1-4.
std::vector<json> planRequests() {
  std::vector<json> out;
  for (const char* scene : {"bin", "table"})
    for (int seed = 1; seed <= 4; ++seed)
      out.push_back({{"scene", scene}, {"seed", seed}, {"time_limit", 30}});
  return out;
}

void BM_ServerInfoRoundTrip(benchmark::State& state) {
  client::RpcClient c("127.0.0.1", server().port());
  for (auto _ : state) benchmark::DoNotOptimize(c.call("server.info", json::object()));
}
BENCHMARK(BM_ServerInfoRoundTrip)->Unit(benchmark::kMicrosecond);

void BM_GraspQualityRoundTrip(benchmark::State& state) {
  client::RpcClient c("127.0.0.1", server().port());
  for (auto _ : state) benchmark::DoNotOptimize(c.call("grasp.quality", kQuality));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_GraspQualityRoundTrip)
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime()
    ->Threads(1)
    ->Threads(2)
    ->Threads(4);

/// Plans of planRequests() split over the benchmark's threads: each thread
/// plans every n-th request. `plan` returns the call's wall time and the
/// planner's planning_time (s); the counter beyond_planning_ms is their
/// mean difference: what a plan costs besides planning.
template <typename Plan>
void planPass(benchmark::State& state, Plan plan) {
  const std::vector<json> requests = planRequests();
  double beyond = 0.0;
  std::int64_t plans = 0;
  for (auto _ : state)
    for (std::size_t i = static_cast<std::size_t>(state.thread_index()); i < requests.size();
         i += static_cast<std::size_t>(state.threads())) {
      const auto began = std::chrono::steady_clock::now();
      const double planning = plan(requests[i]);
      beyond += std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count() -
                planning;
      ++plans;
    }
  state.SetItemsProcessed(plans);
  state.counters["beyond_planning_ms"] = benchmark::Counter(
      1e3 * beyond / static_cast<double>(plans), benchmark::Counter::kAvgThreads);
}

/// planGrasp called directly, one plan per thread at a time
/// (beyond_planning_ms: parsing the params and the planner's tear-down).
void BM_PlansDirect(benchmark::State& state) {
  const service::PlanningCatalog& catalog = server().catalog();
  planPass(state, [&](const json& params) {
    const planner::PlanRequest r = service::planRequestFromJson(params, catalog, {60.0});
    const planner::PlanResult result = planner::planGrasp(catalog.world(), r);
    if (!result.success) state.SkipWithError("a plan failed");
    return result.stats.planning_time;
  });
}
BENCHMARK(BM_PlansDirect)
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Threads(1)
    ->Threads(kWorkers)
    ->Iterations(3);

/// The same plans through the server with kWorkers workers, each benchmark
/// thread one client connection (beyond_planning_ms adds the request, the
/// queue, the result's JSON and the socket).
void BM_PlansViaServer(benchmark::State& state) {
  client::RpcClient c("127.0.0.1", server().port());
  planPass(state, [&](const json& params) {
    const json result = c.call("plan", params);
    if (!result.at("success").get<bool>()) state.SkipWithError("a plan failed");
    return result.at("stats").at("planning_time").get<double>();
  });
}
BENCHMARK(BM_PlansViaServer)
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Threads(kWorkers)
    ->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
