// Synthetic depth images: exact depths without noise, the target's mask,
// the noise model's spread and lost pixels, and a rendered view read back
// as a scene's obstacle.
#include "robot/depth_renderer.h"
#include "robot/sensor_files.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/atomic_file.h"
#include "robot/primitive_meshes.h"

namespace hfts::robot {
namespace {

namespace fs = std::filesystem;

/// A wall (a box 2 m wide and high, 2 cm thick) whose front face is at x =
/// 1, and a camera at the origin looking along +x.
Scene wallScene() {
  Scene scene;
  scene.name = "wall";
  Obstacle wall;
  wall.name = "wall";
  wall.type = Obstacle::Type::kBox;
  wall.size = Eigen::Vector3d(0.02, 2.0, 2.0);
  wall.pose.translation() = Eigen::Vector3d(1.01, 0.0, 0.0);
  scene.obstacles.push_back(wall);
  return scene;
}

DepthView camera() {
  DepthView view = DepthView::withFieldOfView(64, 48, 1.0);
  view.pose = lookAt(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX());
  return view;
}

TEST(DepthRenderer, ACameraLookingAlongXHasItsRowsDownAndColumnsToTheRight) {
  const Eigen::Isometry3d pose = lookAt(Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 1));
  EXPECT_TRUE(pose.linear().col(0).isApprox(-Eigen::Vector3d::UnitY()));  // right
  EXPECT_TRUE(pose.linear().col(1).isApprox(-Eigen::Vector3d::UnitZ()));  // down
  EXPECT_TRUE(pose.linear().col(2).isApprox(Eigen::Vector3d::UnitX()));   // the view
  EXPECT_NEAR(pose.linear().determinant(), 1.0, 1e-12);
}

TEST(DepthRenderer, WithoutNoiseEveryPixelSeesTheWallAtItsDepth) {
  const RenderedDepth r = renderDepth(wallScene(), nullptr, Eigen::Isometry3d::Identity(), camera(),
                                      DepthNoise::none());
  for (const float d : r.image.depths) EXPECT_NEAR(d, 1.0, 1e-5);
  for (const std::uint8_t m : r.target_mask) EXPECT_EQ(m, 0);
  // Back through the pinhole: the points lie on the wall's face.
  const Vertices points = depthToPoints(r.image, camera().camera);
  ASSERT_EQ(points.rows(), 64 * 48);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const Eigen::Vector3d world = camera().pose * Eigen::Vector3d(points.row(i));
    EXPECT_NEAR(world.x(), 1.0, 1e-5);
  }
}

TEST(DepthRenderer, TheMaskIsWhereTheTargetIsSeen) {
  const TriangleMesh cube = boxMesh(Eigen::Vector3d::Constant(0.1));
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.5, 0.0, 0.0);
  const RenderedDepth r = renderDepth(wallScene(), &cube, pose, camera(), DepthNoise::none());
  const DepthView view = camera();
  int masked = 0;
  for (int v = 0; v < 48; ++v)
    for (int u = 0; u < 64; ++u) {
      const std::size_t pixel = std::size_t(v) * 64 + std::size_t(u);
      masked += r.target_mask[pixel];
      EXPECT_NEAR(r.image.depths[pixel], r.target_mask[pixel] ? 0.45 : 1.0, 1e-5);
    }
  // The cube's face, 0.1 m at 0.45 m: 0.1 / 0.45 * fx pixels on a side.
  const double side = 0.1 / 0.45 * view.camera.fx;
  EXPECT_NEAR(masked, side * side, 2 * 2 * side + 4);
}

TEST(DepthRenderer, NoiseSpreadsDepthsAsTheModelSaysAndGrazingPixelsAreLost) {
  DepthView view = DepthView::withFieldOfView(200, 150, 0.3);
  view.pose = lookAt(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX());
  DepthNoise noise;
  noise.dropout = 0.1;
  const RenderedDepth r =
      renderDepth(wallScene(), nullptr, Eigen::Isometry3d::Identity(), view, noise);
  double sum = 0, squares = 0;
  int seen = 0;
  for (const float depth : r.image.depths) {
    if (depth == 0.0f) continue;
    const double d = depth;
    ++seen;
    sum += d;
    squares += d * d;
  }
  const double mean = sum / seen, sigma = std::sqrt(squares / seen - mean * mean);
  const double expected = noise.sigma_base + noise.sigma_quadratic * 0.6 * 0.6;
  EXPECT_NEAR(mean, 1.0, 3 * expected / std::sqrt(seen) + 1e-4);
  EXPECT_NEAR(sigma, expected, 0.1 * expected);
  EXPECT_NEAR(seen / 30000.0, 0.9, 0.01);  // dropout 0.1
  // A wall seen almost edge on (80 +- 3 degrees from its normal): lost.
  view = DepthView::withFieldOfView(200, 150, 0.1);
  const Eigen::Vector3d eye(0.5, 0.8, 0.0);
  view.pose = lookAt(eye, eye + Eigen::Vector3d(std::cos(0.17), std::sin(0.17), 0));
  Scene side = wallScene();
  side.obstacles[0].pose.translation() = Eigen::Vector3d(1.5, 1.0, 0.0);
  side.obstacles[0].size = Eigen::Vector3d(2.0, 0.02, 2.0);  // its face along x at y = 0.99
  auto seenPixels = [&](const DepthNoise& model) {
    const RenderedDepth picture =
        renderDepth(side, nullptr, Eigen::Isometry3d::Identity(), view, model);
    return std::count_if(picture.image.depths.begin(), picture.image.depths.end(),
                         [](float d) { return d > 0.0f; });
  };
  EXPECT_EQ(seenPixels(DepthNoise::none()), 200 * 150);  // every ray meets the wall
  EXPECT_EQ(seenPixels(DepthNoise{}), 0);
}

TEST(DepthRenderer, ARenderedViewReadsBackAsAnObstacleHoldingTheSeenSurface) {
  const fs::path dir = fs::temp_directory_path() / "hfts-depth-renderer-test";
  fs::create_directories(dir);
  const DepthView view = camera();
  const RenderedDepth r =
      renderDepth(wallScene(), nullptr, Eigen::Isometry3d::Identity(), view, DepthNoise{});
  core::writeFileAtomically(dir / "view.png", encodeDepthPng(r.image));
  const DepthImage back = readDepthImage(dir / "view.png", 0.001);
  ASSERT_EQ(back.depths.size(), r.image.depths.size());
  for (std::size_t i = 0; i < back.depths.size(); ++i)
    EXPECT_NEAR(back.depths[i], r.image.depths[i], 0.0005 + 1e-6);  // millimetres
  const Vertices seen = depthToPoints(back, view.camera);
  const VoxelCloud cloud = voxelize(seen, CloudOptions{});
  const double v = cloud.options.voxel;
  auto occupied = [&](const Eigen::Vector3d& p) {
    return cloud.isOccupied(static_cast<int>(std::floor(p.x() / v)),
                            static_cast<int>(std::floor(p.y() / v)),
                            static_cast<int>(std::floor(p.z() / v)));
  };
  for (Eigen::Index i = 0; i < seen.rows(); ++i) EXPECT_TRUE(occupied(seen.row(i)));
  // The voxels hug the wall's face (z = 1 in the camera's frame): within
  // the radius, four standard deviations of noise and the millimetre steps.
  const double reach = cloud.options.radius + 4 * 0.0019 + 0.0005;
  for (const auto& box : cloud.boxes()) {
    EXPECT_GT(box.first.z() + v / 2, 1.0 - reach);
    EXPECT_LT(box.first.z() - v / 2, 1.0 + reach);
  }
  // And they hold most of the face the camera saw (one point per voxel
  // column at this resolution: a point pushed a voxel away by the noise
  // leaves its column empty).
  const Vertices exact = depthToPoints(
      renderDepth(wallScene(), nullptr, Eigen::Isometry3d::Identity(), view, DepthNoise::none())
          .image,
      view.camera);
  int held = 0;
  for (Eigen::Index i = 0; i < exact.rows(); ++i)
    held += occupied(Eigen::Vector3d(exact.row(i)) + Eigen::Vector3d(0, 0, 0.001)) ? 1 : 0;
  EXPECT_GT(held, 0.9 * static_cast<double>(exact.rows()));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hfts::robot
