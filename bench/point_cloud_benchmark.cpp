// point_cloud_benchmark: point clouds as obstacles (docs/point_clouds.md).
// What building the obstacle costs against the number of points and from a
// 640 x 480 depth image, and what a check against it costs: the sphere
// tier's bound (one grid read, whatever the number of points), FCL's octree
// for one sphere, the KR5 checked whole with and without the sphere tier,
// and the planner's scene from three views (asPlannerSees against its
// carvings applied one after the other).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>
#include <random>

#include "core/atomic_file.h"
#include "robot/collision_checker.h"
#include "robot/collision_model.h"
#include "robot/depth_renderer.h"
#include "robot/point_cloud.h"
#include "robot/robot_model.h"
#include "robot/scene.h"
#include "robot/sensed_scene.h"
#include "robot/sensor_files.h"

namespace {

using namespace hfts;

/// `n` points with 3 mm of noise on a table top (1 x 1 m) and two shelf
/// boards above it, in front of the robot (world frame).
Vertices shelfCloud(std::int64_t n) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.003);
  Vertices points(n, 3);
  const double heights[3] = {0.3, 0.6, 0.9};
  for (std::int64_t i = 0; i < n; ++i) {
    const int board = static_cast<int>(i % 3);
    const double width = board == 0 ? 1.0 : 0.6;
    points.row(i) << 0.4 + width * u(rng) + noise(rng), -0.5 + u(rng) + noise(rng),
        heights[board] + noise(rng);
  }
  return points;
}

/// 4096 points in the clouds' region, where the checks are asked.
std::vector<Eigen::Vector3d> queryPoints() {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Eigen::Vector3d> queries(4096);
  for (Eigen::Vector3d& q : queries)
    q = Eigen::Vector3d(0.4 + u(rng), -0.5 + u(rng), 0.2 + 0.8 * u(rng));
  return queries;
}

robot::Scene sceneOf(const robot::VoxelCloud& built) {
  auto cloud = std::make_shared<robot::VoxelCloud>(built);
  robot::Obstacle o;
  o.name = "cloud";
  o.type = robot::Obstacle::Type::kPoints;
  o.mesh = cloud->mesh;
  o.distance_grid = std::shared_ptr<const db::DistanceGrid>(cloud, &cloud->distances);
  o.cloud = cloud;
  robot::Scene scene;
  scene.name = "cloud";
  scene.obstacles.push_back(o);
  return scene;
}

const robot::RobotModel& kr5() {
  static const robot::RobotModel model =
      robot::RobotModel::load(std::string(HFTS_SOURCE_DIR) + "/robots/kr5_sdh/kr5_sdh.json");
  return model;
}

const robot::CollisionModel& kr5Collision() {
  static const std::shared_ptr<const robot::CollisionModel> model =
      robot::buildCollisionModel(kr5());
  return *model;
}

void BM_Voxelize(benchmark::State& state) {
  const Vertices points = shelfCloud(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(robot::voxelize(points));
  state.counters["points"] = static_cast<double>(state.range(0));
}
BENCHMARK(BM_Voxelize)->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);

/// The sphere tier's bound at a point: the same read as its kernel's.
void BM_SphereTierBound(benchmark::State& state) {
  const robot::VoxelCloud cloud = robot::voxelize(shelfCloud(state.range(0)));
  const std::vector<Eigen::Vector3d> queries = queryPoints();
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(cloud.distances.lowerBound(queries[i++ & 4095]));
  state.counters["voxels"] = static_cast<double>(cloud.occupied_count);
}
BENCHMARK(BM_SphereTierBound)->Arg(10000)->Arg(100000)->Arg(1000000);

/// FCL's octree against one 5 cm sphere (CollisionScene::sphereTouchesObstacles).
void BM_FclOctreeSphere(benchmark::State& state) {
  const robot::Scene scene = sceneOf(robot::voxelize(shelfCloud(state.range(0))));
  const robot::CollisionScene collision(kr5Collision(), scene, nullptr);
  const std::vector<Eigen::Vector3d> queries = queryPoints();
  std::size_t i = 0;
  for (auto _ : state)
    benchmark::DoNotOptimize(collision.sphereTouchesObstacles(queries[i++ & 4095], 0.05));
}
BENCHMARK(BM_FclOctreeSphere)->Arg(10000)->Arg(100000)->Arg(1000000);

/// The KR5 and its hand checked whole at random configurations; second
/// argument 1: with the sphere tier (the default), 0: FCL alone.
void BM_RobotCheck(benchmark::State& state) {
  const robot::Scene scene = sceneOf(robot::voxelize(shelfCloud(state.range(0))));
  robot::CollisionChecker checker(kr5Collision(), scene, nullptr);
  checker.setSphereTier(state.range(1) != 0);
  const robot::RobotModel& model = kr5();
  std::mt19937_64 rng(5);
  std::vector<Eigen::VectorXd> qs(1024, Eigen::VectorXd(model.numDofs()));
  for (Eigen::VectorXd& q : qs)
    for (int d = 0; d < model.numDofs(); ++d)
      q(d) = std::uniform_real_distribution<double>(model.lowerLimits()(d),
                                                    model.upperLimits()(d))(rng);
  std::size_t i = 0, colliding = 0;
  for (auto _ : state) colliding += checker.inCollision(qs[i++ & 1023]) ? 1 : 0;
  state.counters["colliding"] = static_cast<double>(colliding) / static_cast<double>(i);
}
BENCHMARK(BM_RobotCheck)
    ->Args({10000, 1})
    ->Args({100000, 1})
    ->Args({1000000, 1})
    ->Args({10000, 0})
    ->Args({100000, 0})
    ->Args({1000000, 0});

/// A 640 x 480 view of a table and a shelf (rendered once, written as a
/// 16-bit PNG) read and turned into an obstacle: PNG decoding, the
/// pinhole, the voxels and their distances.
void BM_DepthImage640x480(benchmark::State& state) {
  const robot::Scene shelf = sceneOf(robot::voxelize(shelfCloud(200000)));
  robot::DepthView view =
      robot::DepthView::withFieldOfView(640, 480, 58.0 * 3.14159265358979 / 180);
  view.pose = robot::lookAt(Eigen::Vector3d(-0.2, 0.0, 1.3), Eigen::Vector3d(0.9, 0.0, 0.4));
  const robot::RenderedDepth rendered =
      robot::renderDepth(shelf, nullptr, Eigen::Isometry3d::Identity(), view, robot::DepthNoise{});
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "hfts_point_cloud_benchmark.png";
  core::writeFileAtomically(file, robot::encodeDepthPng(rendered.image));
  std::size_t points = 0;
  for (auto _ : state) {
    const Vertices seen = robot::depthToPoints(robot::readDepthImage(file, 0.001), view.camera);
    points = static_cast<std::size_t>(seen.rows());
    benchmark::DoNotOptimize(robot::voxelize(seen));
  }
  state.counters["points"] = static_cast<double>(points);
  std::filesystem::remove(file);
}
BENCHMARK(BM_DepthImage640x480)->Unit(benchmark::kMillisecond);

/// The shelf cloud seen by three 640 x 480 cameras (left, front, right),
/// each view an obstacle with its shadows, as a scene file's depth images
/// become; and a 6 cm box standing on the table as the target.
struct ThreeViews {
  robot::Scene scene;
  db::ObjectDatabase target;
};
const ThreeViews& threeViews() {
  static const ThreeViews views = [] {
    ThreeViews out;
    const robot::Scene shelf = sceneOf(robot::voxelize(shelfCloud(200000)));
    const Eigen::Vector3d centre(0.9, 0.0, 0.4);
    const Eigen::Vector3d eyes[3] = {{0.4, -1.0, 1.2}, {-0.2, 0.0, 1.3}, {0.4, 1.0, 1.2}};
    for (int v = 0; v < 3; ++v) {
      robot::DepthView view =
          robot::DepthView::withFieldOfView(640, 480, 58.0 * 3.14159265358979 / 180);
      view.pose = robot::lookAt(eyes[v], centre);
      const robot::RenderedDepth rendered = robot::renderDepth(
          shelf, nullptr, Eigen::Isometry3d::Identity(), view, robot::DepthNoise{});
      robot::CloudOptions options;
      options.viewpoint = eyes[v];
      const Vertices seen = robot::depthToPoints(rendered.image, view.camera);
      const Vertices world = (view.pose * seen.transpose()).transpose();
      auto cloud = std::make_shared<robot::VoxelCloud>(robot::voxelize(world, options));
      robot::Obstacle o;
      o.name = "view" + std::to_string(v);
      o.type = robot::Obstacle::Type::kPoints;
      o.mesh = cloud->mesh;
      o.distance_grid = std::shared_ptr<const db::DistanceGrid>(cloud, &cloud->distances);
      o.cloud = std::move(cloud);
      out.scene.obstacles.push_back(std::move(o));
    }
    TriangleMesh box = hfts::boxMesh(Eigen::Vector3d(0.06, 0.06, 0.06));
    box.vertices.col(2).array() += 0.03;
    out.target.geometry.mesh_vertices = box.vertices;
    out.target.geometry.mesh_triangles = box.triangles;
    out.target.geometry.distance_grid = db::buildDistanceGrid(box, true);
    out.scene.target_object = "box";
    out.scene.target_pose.translation() = Eigen::Vector3d(0.7, 0.0, 0.3);
    return out;
  }();
  return views;
}

/// The planner's scene from the three views: argument 1, asPlannerSees
/// (each cloud carved once); 0, the carvings one after the other.
void BM_PlannerSceneFromThreeViews(benchmark::State& state) {
  const ThreeViews& views = threeViews();
  const robot::RobotModel& model = kr5();
  const db::ObjectGeometry& box = views.target.geometry;
  for (auto _ : state) {
    if (state.range(0) != 0) {
      benchmark::DoNotOptimize(
          robot::asPlannerSees(views.scene, views.target, model, model.home()));
    } else {
      benchmark::DoNotOptimize(robot::withRobotCarved(
          robot::withHiddenSide(robot::withTargetCarved(robot::withSeenSpaceCarved(views.scene),
                                                        box.distance_grid, box.mesh_vertices),
                                views.target),
          model, model.home()));
    }
  }
}
BENCHMARK(BM_PlannerSceneFromThreeViews)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
