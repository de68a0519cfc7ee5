// Speed of the planner's inner loops (figures in docs/performance.md):
//   build/bin/planner_benchmark --benchmark_min_time=1
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "grasp/grasp_quality.h"
#include "grasp/hand_map_builder.h"
#include "planner/grasp_motion_planner.h"
#include "planner/planning_world.h"
#include "planner/time_parameterization.h"
#include "preprocess/database_builder.h"
#include "robot/arm_ik.h"
#include "robot/collision_checker.h"
#include "robot/kinematics.h"

namespace {

using namespace hfts;

const std::filesystem::path kSource = HFTS_SOURCE_DIR;

const robot::RobotModel& robot() {
  static const robot::RobotModel model =
      robot::RobotModel::load(kSource / "robots/kr5_sdh/kr5_sdh.json");
  return model;
}

const robot::CollisionModel& collision() {
  static const std::shared_ptr<const robot::CollisionModel> model =
      robot::buildCollisionModel(robot());
  return *model;
}

// What a robot's collision model costs to derive (docs/performance.md,
// "Deriving the collision model"): its sphere covering and pair maps, from
// the loaded kinematic model, once per robot when a planning world loads.
const char* const kRobots[] = {"kr5_sdh", "ur5e_allegro", "panda_gripper"};

void BM_BuildCollisionModel(benchmark::State& state) {
  const std::string name = kRobots[state.range(0)];
  const robot::RobotModel model =
      robot::RobotModel::load(kSource / "robots" / name / (name + ".json"));
  std::size_t spheres = 0;
  for (auto _ : state) {
    const auto built = robot::buildCollisionModel(model);
    spheres = built->spheres.numSpheres();
    benchmark::DoNotOptimize(built.get());
  }
  state.SetLabel(name);
  state.counters["spheres"] = static_cast<double>(spheres);
}
BENCHMARK(BM_BuildCollisionModel)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

Eigen::VectorXd randomConfiguration(std::mt19937_64& rng) {
  Eigen::VectorXd q(robot().numDofs());
  for (Eigen::Index d = 0; d < q.size(); ++d)
    q(d) = std::uniform_real_distribution<double>(robot().lowerLimits()(d),
                                                  robot().upperLimits()(d))(rng);
  return q;
}

void BM_ForwardKinematicsAllLinks(benchmark::State& state) {
  std::mt19937_64 rng(1);
  const Eigen::VectorXd q = randomConfiguration(rng);
  robot::LinkPoses poses;
  for (auto _ : state) {
    robot::forwardKinematics(robot(), q, poses);
    benchmark::DoNotOptimize(poses.data());
  }
  state.counters["links"] = static_cast<double>(poses.size());
}
BENCHMARK(BM_ForwardKinematicsAllLinks);

void BM_ClosedFormIkAllSolutions(benchmark::State& state) {
  const robot::ArmIk ik(robot());
  std::mt19937_64 rng(2);
  std::vector<Eigen::Isometry3d> targets;
  for (int i = 0; i < 256; ++i) targets.push_back(ik.flangePose(randomConfiguration(rng).head(6)));
  std::size_t i = 0, solutions = 0;
  for (auto _ : state) {
    const auto found = ik.solveFlange(targets[i++ % targets.size()], rng);
    solutions += found.size();
    benchmark::DoNotOptimize(found.data());
  }
  state.counters["solutions_per_pose"] =
      static_cast<double>(solutions) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_ClosedFormIkAllSolutions);

/// Every IK solution of 256 random reachable flange poses of a bundled
/// robot's arm, closed form (arg 0) against damped least squares from 30
/// seeds (arg 1) on the same poses: the UR5e (UR-type closed form) and the
/// Panda (numerical only; its 7th joint makes the continuum).
void runArmIk(benchmark::State& state, const char* config) {
  const robot::RobotModel model = robot::RobotModel::load(kSource / config);
  const robot::ArmIk ik(model);
  std::mt19937_64 rng(2);
  std::vector<Eigen::Isometry3d> targets;
  for (int i = 0; i < 256; ++i) {
    Eigen::VectorXd arm(model.numArmDofs());
    for (int d = 0; d < model.numArmDofs(); ++d)
      arm(d) = std::uniform_real_distribution<double>(model.lowerLimits()(d),
                                                      model.upperLimits()(d))(rng);
    targets.push_back(ik.flangePose(arm));
  }
  const bool numerical = state.range(0) == 1;
  std::size_t i = 0, solutions = 0;
  for (auto _ : state) {
    const Eigen::Isometry3d& target = targets[i++ % targets.size()];
    const auto found = numerical ? ik.solveNumerically(target, rng) : ik.solveFlange(target, rng);
    solutions += found.size();
    benchmark::DoNotOptimize(found.data());
  }
  state.counters["solutions_per_pose"] =
      static_cast<double>(solutions) / static_cast<double>(state.iterations());
}
void BM_Ur5eArmIk(benchmark::State& state) {
  runArmIk(state, "robots/ur5e_allegro/ur5e_allegro.json");
}
BENCHMARK(BM_Ur5eArmIk)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
void BM_PandaArmIk(benchmark::State& state) {
  runArmIk(state, "robots/panda_gripper/panda_gripper.json");
}
BENCHMARK(BM_PandaArmIk)->Arg(1)->Unit(benchmark::kMicrosecond);

/// 256 random 3-contact grasps on a 5 cm sphere (K = 8, mu = 0.5).
std::vector<grasp::GraspQualityRequest> randomGrasps() {
  std::mt19937_64 rng(4);
  std::normal_distribution<double> g;
  std::vector<grasp::GraspQualityRequest> requests(256);
  for (auto& r : requests) {
    r.positions.resize(3, 3);
    r.normals.resize(3, 3);
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d p = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
      r.positions.col(i) = 0.05 * p;
      r.normals.col(i) = (-p + 0.2 * Eigen::Vector3d(g(rng), g(rng), g(rng))).normalized();
    }
    r.torque_scale = 0.05;
  }
  return requests;
}

void runGraspQuality(benchmark::State& state,
                     const std::vector<grasp::GraspQualityRequest>& requests) {
  std::size_t i = 0, stable = 0;
  for (auto _ : state) stable += grasp::graspQuality(requests[i++ % requests.size()]).epsilon > 0;
  state.counters["stable"] = static_cast<double>(stable) / static_cast<double>(state.iterations());
}

/// Epsilon of the random grasps, most of them (71 %) not force closure.
void BM_GraspQuality3Contacts(benchmark::State& state) {
  runGraspQuality(state, randomGrasps());
}
BENCHMARK(BM_GraspQuality3Contacts);

/// The same for the force-closure grasps among them only (by Qhull), whose
/// epsilon cannot be settled by finding one facet the origin lies beyond.
void BM_GraspQuality3ContactsStable(benchmark::State& state) {
  std::vector<grasp::GraspQualityRequest> requests = randomGrasps();
  requests.erase(std::remove_if(requests.begin(), requests.end(),
                                [](grasp::GraspQualityRequest r) {
                                  r.use_qhull = true;
                                  return grasp::graspQuality(r).epsilon == 0.0;
                                }),
                 requests.end());
  runGraspQuality(state, requests);
}
BENCHMARK(BM_GraspQuality3ContactsStable);

/// Large wrench sets, as a grasp.quality call may send (contacts x cone
/// edges up to kMaxQualityWrenches): contacts around a 5 cm sphere with perturbed inward
/// normals, mu = 0.5. Arguments: contacts, cone edges, 1 for Qhull. The
/// incremental hull inserts only the wrenches that can change the depth;
/// Qhull builds the whole 6-D hull, whose size grows with the cube of the
/// number of wrenches.
void BM_GraspQualityManyWrenches(benchmark::State& state) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g;
  std::vector<grasp::GraspQualityRequest> requests(8);
  for (auto& r : requests) {
    const auto contacts = static_cast<Eigen::Index>(state.range(0));
    r.positions.resize(3, contacts);
    r.normals.resize(3, contacts);
    for (Eigen::Index i = 0; i < contacts; ++i) {
      const Eigen::Vector3d p = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
      r.positions.col(i) = 0.05 * p;
      r.normals.col(i) = (-p + 0.2 * Eigen::Vector3d(g(rng), g(rng), g(rng))).normalized();
    }
    r.torque_scale = 0.05;
    r.cone_edges = static_cast<int>(state.range(1));
    r.use_qhull = state.range(2) != 0;
  }
  runGraspQuality(state, requests);
}
BENCHMARK(BM_GraspQualityManyWrenches)
    ->ArgNames({"contacts", "edges", "qhull"})
    ->Args({3, 64, 0})
    ->Args({3, 64, 1})
    ->Args({4, 64, 0})
    ->Args({32, 8, 0})
    ->Unit(benchmark::kMillisecond);

/// Which configurations a collision benchmark checks.
enum class Configurations {
  kRandom,  ///< uniform within the limits (72 % collide: early exits)
  kFree,    ///< collision-free only: no early exit, the worst case
  kClear,   ///< free and settled by the sphere tier alone (no FCL call)
};

/// A bundled scene's checker (KR5 + SDH, the scene's target object).
struct SceneChecker {
  explicit SceneChecker(const std::string& name)
      : scene(robot::loadScene(kSource / ("objects/scenes/" + name + ".json"))) {
    std::filesystem::path mesh;
    for (const auto& entry : std::filesystem::directory_iterator(kSource / "objects/meshes"))
      if (entry.path().stem() == scene.target_object && entry.path().extension() != ".json")
        mesh = entry.path();
    target = preprocess::buildObjectDatabaseFromFile(mesh, {}).database.geometry;
    checker = std::make_unique<robot::CollisionChecker>(collision(), scene, &target);
  }
  robot::Scene scene;
  db::ObjectGeometry target;
  std::unique_ptr<robot::CollisionChecker> checker;
};

/// 1024 configurations of the kind asked for (seed 3), chosen with the
/// two-tier checker so that both checkers get the same ones.
std::vector<Eigen::VectorXd> configurations(robot::CollisionChecker& checker, Configurations kind) {
  std::mt19937_64 rng(3);
  std::vector<Eigen::VectorXd> out;
  while (out.size() < 1024) {
    const Eigen::VectorXd q = randomConfiguration(rng);
    const std::uint64_t settled = checker.sphereSettledCount();
    const bool free = !checker.inCollision(q);
    const bool clear = checker.sphereSettledCount() > settled;
    if (kind == Configurations::kRandom || (kind == Configurations::kFree && free) ||
        (kind == Configurations::kClear && clear))
      out.push_back(q);
  }
  return out;
}

/// Full-robot collision checks (environment, target object, self) of
/// configurations in a bundled scene. `spheres`: the two-tier checker
/// (spheres, then FCL on the touching pairs) or FCL alone. The median and
/// 90th percentile of single checks are reported as counters
/// (microseconds), and the share the sphere tier settled without FCL.
void BM_CollisionCheck(benchmark::State& state, const std::string& scene, Configurations kind,
                       bool spheres) {
  SceneChecker s(scene);
  robot::CollisionChecker& checker = *s.checker;
  const std::vector<Eigen::VectorXd> qs = configurations(checker, kind);
  checker.setSphereTier(spheres);
  std::vector<double> micros;
  std::size_t i = 0, colliding = 0;
  const std::uint64_t checksBefore = checker.checkCount(),
                      settledBefore = checker.sphereSettledCount();
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    colliding += checker.inCollision(qs[i++ % qs.size()]);
    micros.push_back(
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start)
            .count());
  }
  std::sort(micros.begin(), micros.end());
  state.counters["median_us"] = micros[micros.size() / 2];
  state.counters["p90_us"] = micros[micros.size() * 9 / 10];
  state.counters["colliding"] = static_cast<double>(colliding) / static_cast<double>(micros.size());
  state.counters["settled"] = static_cast<double>(checker.sphereSettledCount() - settledBefore) /
                              static_cast<double>(checker.checkCount() - checksBefore);
}

#define HFTS_COLLISION_BENCHMARKS(scene)                                            \
  BENCHMARK_CAPTURE(BM_CollisionCheck, scene##_random_fcl, std::string(#scene),     \
                    Configurations::kRandom, false)                                 \
      ->Unit(benchmark::kMicrosecond);                                              \
  BENCHMARK_CAPTURE(BM_CollisionCheck, scene##_random_spheres, std::string(#scene), \
                    Configurations::kRandom, true)                                  \
      ->Unit(benchmark::kMicrosecond);                                              \
  BENCHMARK_CAPTURE(BM_CollisionCheck, scene##_free_fcl, std::string(#scene),       \
                    Configurations::kFree, false)                                   \
      ->Unit(benchmark::kMicrosecond);                                              \
  BENCHMARK_CAPTURE(BM_CollisionCheck, scene##_free_spheres, std::string(#scene),   \
                    Configurations::kFree, true)                                    \
      ->Unit(benchmark::kMicrosecond);                                              \
  BENCHMARK_CAPTURE(BM_CollisionCheck, scene##_clear_fcl, std::string(#scene),      \
                    Configurations::kClear, false)                                  \
      ->Unit(benchmark::kMicrosecond);                                              \
  BENCHMARK_CAPTURE(BM_CollisionCheck, scene##_clear_spheres, std::string(#scene),  \
                    Configurations::kClear, true)                                   \
      ->Unit(benchmark::kMicrosecond)
HFTS_COLLISION_BENCHMARKS(table);
HFTS_COLLISION_BENCHMARKS(shelf);
HFTS_COLLISION_BENCHMARKS(bin);

/// Straight motions of 0.5 (Eq. (3) metric) from collision-free starts
/// whose every state at the tree resolution (0.02: 25 states) is free,
/// validated with isMotionValid; the median and 90th percentile of single
/// validations as counters (microseconds). `clearOnly`: only motions whose
/// every state the sphere tier settles alone (no FCL call).
void BM_MotionValidation(benchmark::State& state, const std::string& scene, bool spheres,
                         bool clearOnly) {
  constexpr double kLength = 0.5, kResolution = 0.02;
  SceneChecker s(scene);
  robot::CollisionChecker& checker = *s.checker;
  std::mt19937_64 rng(5);
  std::vector<std::pair<Eigen::VectorXd, Eigen::VectorXd>> motions;
  while (motions.size() < 256) {
    const Eigen::VectorXd a = randomConfiguration(rng);
    Eigen::VectorXd direction = randomConfiguration(rng) - a;
    const Eigen::VectorXd b =
        a + direction * (kLength / checker.metric().distance(a, a + direction));
    if (!robot().withinLimits(b) || checker.inCollision(a)) continue;
    const std::uint64_t checks = checker.checkCount(), settled = checker.sphereSettledCount();
    if (!checker.isMotionValid(a, b, kResolution)) continue;
    if (clearOnly && checker.sphereSettledCount() - settled < checker.checkCount() - checks)
      continue;
    motions.emplace_back(a, b);
  }
  checker.setSphereTier(spheres);
  std::vector<double> micros;
  std::size_t i = 0, valid = 0;
  for (auto _ : state) {
    const auto& [a, b] = motions[i++ % motions.size()];
    const auto start = std::chrono::steady_clock::now();
    valid += checker.isMotionValid(a, b, kResolution);
    micros.push_back(
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start)
            .count());
  }
  std::sort(micros.begin(), micros.end());
  state.counters["median_us"] = micros[micros.size() / 2];
  state.counters["p90_us"] = micros[micros.size() * 9 / 10];
  state.counters["valid"] = static_cast<double>(valid) / static_cast<double>(micros.size());
}
#define HFTS_MOTION_BENCHMARKS(scene)                                                            \
  BENCHMARK_CAPTURE(BM_MotionValidation, scene##_fcl, std::string(#scene), false, false)         \
      ->Unit(benchmark::kMicrosecond);                                                           \
  BENCHMARK_CAPTURE(BM_MotionValidation, scene##_spheres, std::string(#scene), true, false)      \
      ->Unit(benchmark::kMicrosecond);                                                           \
  BENCHMARK_CAPTURE(BM_MotionValidation, scene##_clear_fcl, std::string(#scene), false, true)    \
      ->Unit(benchmark::kMicrosecond);                                                           \
  BENCHMARK_CAPTURE(BM_MotionValidation, scene##_clear_spheres, std::string(#scene), true, true) \
      ->Unit(benchmark::kMicrosecond)
HFTS_MOTION_BENCHMARKS(table);
HFTS_MOTION_BENCHMARKS(shelf);
HFTS_MOTION_BENCHMARKS(bin);

/// A time-optimal trajectory (planner/time_parameterization.h) through
/// `waypoints` random configurations a random walk apart (each joint
/// +-0.4 rad per step), the KR5 + SDH's limits, sampled at 100 Hz; one
/// path per iteration from a fixed list of 16.
void BM_TimeOptimalTrajectory(benchmark::State& state) {
  std::mt19937_64 rng(1);
  std::vector<std::vector<Eigen::VectorXd>> paths(16);
  for (auto& path : paths) {
    Eigen::VectorXd q = robot().home();
    for (int i = 0; i < state.range(0); ++i) {
      for (Eigen::Index d = 0; d < q.size(); ++d)
        q(d) = std::clamp(q(d) + std::uniform_real_distribution<double>(-0.4, 0.4)(rng),
                          robot().lowerLimits()(d), robot().upperLimits()(d));
      path.push_back(q);
    }
  }
  std::size_t next = 0;
  double seconds = 0.0;
  for (auto _ : state) {
    const planner::TimeOptimalTrajectory t(paths[next++ % paths.size()], robot().maxVelocities(),
                                           robot().maxAccelerations());
    benchmark::DoNotOptimize(t.sample(100.0));
    seconds += t.duration();
  }
  state.counters["trajectory_s"] =
      benchmark::Counter(seconds / static_cast<double>(state.iterations()));
}
BENCHMARK(BM_TimeOptimalTrajectory)->Arg(5)->Arg(20)->Unit(benchmark::kMillisecond);

/// What starting a plan costs before any search: planGrasp with a time
/// limit of 0 (the request checked, the problem set up: checker, space,
/// parameters, contact mask, HFTS; the search set up and stopped at once),
/// for `threads` racing copies (each sets up its own problem in its own
/// thread), without and with `physics_check` (which compiles the goal
/// checks' MuJoCo model first). The KR5 in the table scene with the mug.
void BM_PlanStartUp(benchmark::State& state) {
  static const std::shared_ptr<const planner::PlanningWorld> world = [] {
    std::map<std::string, db::ObjectDatabase> objects;
    objects.emplace(
        "mug",
        preprocess::buildObjectDatabaseFromFile(kSource / "objects/meshes/mug.ply", {}).database);
    return std::make_shared<planner::PlanningWorld>(robot(), grasp::buildHandMap(robot()),
                                                    std::move(objects));
  }();
  planner::PlanRequest request;
  request.scene = robot::loadScene(kSource / "objects/scenes/table.json");
  request.object = "mug";
  request.time_limit = 0.0;
  request.parameters["threads"] = std::to_string(state.range(0));
  request.parameters["physics_check"] = std::to_string(state.range(1));
  for (auto _ : state) {
    const planner::PlanResult result = planner::planGrasp(*world, request);
    benchmark::DoNotOptimize(result.success);
  }
}
BENCHMARK(BM_PlanStartUp)
    ->ArgNames({"threads", "physics_check"})
    ->ArgsProduct({{1, 2, 4}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
