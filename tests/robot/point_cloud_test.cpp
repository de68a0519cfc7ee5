// Point clouds and depth images as obstacles: the voxels they occupy, the
// sphere tier's distances to them, the files they come from, and the two
// tiers of the checker agreeing on a scene made of them.
#include "robot/point_cloud.h"
#include "robot/sensor_files.h"

#include <gtest/gtest.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "core/base64.h"
#include "core/invalid_argument.h"
#include "hfts_db/object_database.h"
#include "robot/collision_checker.h"
#include "robot/kinematics.h"
#include "robot/scene.h"
#include "robot/sensed_scene.h"
#include "robot_fixture.h"

namespace hfts::robot {
namespace {

namespace fs = std::filesystem;

Vertices rows(std::initializer_list<Eigen::Vector3d> points) {
  Vertices out(static_cast<Eigen::Index>(points.size()), 3);
  Eigen::Index i = 0;
  for (const Eigen::Vector3d& p : points) out.row(i++) = p.transpose();
  return out;
}

/// Exact distance from p to the union of the occupied voxels' boxes.
double exactDistance(const VoxelCloud& cloud, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  const double v = cloud.options.voxel;
  for (int k = cloud.first[2]; k < cloud.first[2] + cloud.dims[2]; ++k)
    for (int j = cloud.first[1]; j < cloud.first[1] + cloud.dims[1]; ++j)
      for (int i = cloud.first[0]; i < cloud.first[0] + cloud.dims[0]; ++i) {
        if (!cloud.isOccupied(i, j, k)) continue;
        const Eigen::Vector3d low = Eigen::Vector3d(i, j, k) * v, high = low.array() + v;
        best = std::min(best, (p - p.cwiseMax(low).cwiseMin(high)).norm());
      }
  return best;
}

/// Points on the surface of a box (centre c, edges e), `n` of them, with
/// Gaussian noise of `sigma` along every axis.
Vertices noisyBox(const Eigen::Vector3d& c, const Eigen::Vector3d& e, int n, double sigma,
                  std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  std::normal_distribution<double> noise(0.0, sigma);
  Vertices out(n, 3);
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d p(u(rng), u(rng), u(rng));
    p(i % 3) = p(i % 3) < 0 ? -0.5 : 0.5;
    out.row(i) =
        (c + p.cwiseProduct(e) + Eigen::Vector3d(noise(rng), noise(rng), noise(rng))).transpose();
  }
  return out;
}

TEST(PointCloud, APointOccupiesItsVoxelAndThoseWithinTheRadius) {
  CloudOptions options;
  options.voxel = 0.01;
  options.radius = 0.0;
  const VoxelCloud alone = voxelize(rows({{0.011, 0.005, 0.005}}), options);
  EXPECT_EQ(alone.occupied_count, 1u);
  EXPECT_TRUE(alone.isOccupied(1, 0, 0));
  options.radius = 0.002;  // reaches voxel (0, 0, 0), 1 mm away, not (1, -1, 0), 5 mm away
  const VoxelCloud grown = voxelize(rows({{0.011, 0.005, 0.005}}), options);
  EXPECT_EQ(grown.occupied_count, 2u);
  EXPECT_TRUE(grown.isOccupied(0, 0, 0));
  EXPECT_TRUE(grown.isOccupied(1, 0, 0));
  EXPECT_FALSE(grown.isOccupied(1, -1, 0));
  // Negative coordinates: voxel -1 spans [-0.01, 0).
  options.radius = 0.0;
  EXPECT_TRUE(voxelize(rows({{-0.001, -0.019, 0.0}}), options).isOccupied(-1, -2, 0));
}

TEST(PointCloud, BehindAPointAsTheSensorLooksIsOccupiedForTheShadowsLength) {
  CloudOptions options;
  options.radius = 0.0;
  options.shadow = 0.1;
  options.viewpoint = Eigen::Vector3d::Zero();
  // A point at the centre of voxel (0, 0, 100), seen from the origin.
  const VoxelCloud cloud = voxelize(rows({{0.005, 0.005, 1.005}}), options);
  for (int k = 100; k <= 110; ++k) EXPECT_TRUE(cloud.isOccupied(0, 0, k)) << k;
  EXPECT_FALSE(cloud.isOccupied(0, 0, 99));   // in front: seen free
  EXPECT_FALSE(cloud.isOccupied(0, 0, 111));  // beyond the shadow
  EXPECT_EQ(cloud.occupied_count, 11u);
  options.viewpoint.reset();  // no viewpoint, no shadow
  EXPECT_EQ(voxelize(rows({{0.005, 0.005, 1.005}}), options).occupied_count, 1u);
  options.shadow = -1;
  EXPECT_THROW(voxelize(rows({{0, 0, 1}}), options), InvalidArgument);
}

TEST(PointCloud, TheDistanceGridBoundsTheDistanceToTheVoxelsFromBelow) {
  std::mt19937_64 rng(3);
  const VoxelCloud cloud =
      voxelize(noisyBox({0.1, -0.05, 0.2}, {0.12, 0.08, 0.03}, 3000, 0.002, rng), CloudOptions{});
  ASSERT_GT(cloud.occupied_count, 100u);
  std::uniform_real_distribution<double> u(-0.15, 0.15);
  int tight = 0;
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3d p =
        Eigen::Vector3d(0.1, -0.05, 0.2) + Eigen::Vector3d(u(rng), u(rng), u(rng));
    const double exact = exactDistance(cloud, p), bound = cloud.distances.lowerBound(p);
    ASSERT_LE(bound, exact + 1e-9) << p.transpose();
    // Within the passes' reach the bound is the node's exact value less the
    // way to the node: at most sqrt(3) voxels short.
    if (exact < 0.05) {
      EXPECT_GE(bound, exact - std::sqrt(3.0) * cloud.options.voxel - 1e-6);
      ++tight;
    }
  }
  EXPECT_GT(tight, 500);
}

TEST(PointCloud, TheOccupiedVoxelsAreItsBoxes) {
  std::mt19937_64 rng(5);
  const VoxelCloud cloud =
      voxelize(noisyBox({0.0, 0.0, 0.0}, {0.1, 0.06, 0.04}, 2000, 0.001, rng), CloudOptions{});
  double volume = 0;
  for (const auto& box : cloud.boxes()) volume += box.second.prod();
  EXPECT_NEAR(volume, cloud.occupied_count * std::pow(cloud.options.voxel, 3), 1e-12);
  EXPECT_EQ(cloud.mesh.triangles.rows(), static_cast<Eigen::Index>(12 * cloud.boxes().size()));
}

TEST(PointCloud, BadOptionsAndEmptyCloudsAreRefusedByName) {
  const Vertices one = rows({{0, 0, 0}});
  auto fieldOf = [](const Vertices& points, const CloudOptions& options) {
    try {
      voxelize(points, options);
    } catch (const InvalidArgument& e) {
      return e.field();
    }
    return std::string("none");
  };
  CloudOptions o;
  o.voxel = 0.0;
  EXPECT_EQ(fieldOf(one, o), "voxel");
  o = {};
  o.radius = -1e-3;
  EXPECT_EQ(fieldOf(one, o), "radius");
  o = {};
  Vertices nan(1, 3);
  nan << std::nan(""), 0, 0;
  EXPECT_EQ(fieldOf(nan, o), "points");
  o.voxel = 0.001;  // 10 m at 1 mm: far over the voxel budget
  EXPECT_EQ(fieldOf(rows({{0, 0, 0}, {10, 10, 10}}), o), "points");
}

TEST(PointCloud, ADepthImageBecomesPointsThroughThePinhole) {
  DepthImage image{3, 2, {1.0f, 0.0f, 2.0f, std::nanf(""), 9.0f, 0.5f}};
  DepthCamera camera;
  camera.fx = 100;
  camera.fy = 200;
  camera.cx = 1;
  camera.cy = 0;
  camera.max_depth = 3.0;
  const Vertices points = depthToPoints(image, camera);
  ASSERT_EQ(points.rows(), 3);  // 0, NaN and 9 m (beyond max_depth) are not seen
  EXPECT_TRUE(points.row(0).isApprox(Eigen::RowVector3d(-0.01, 0.0, 1.0)));
  EXPECT_TRUE(points.row(1).isApprox(Eigen::RowVector3d(0.02, 0.0, 2.0)));
  EXPECT_TRUE(points.row(2).isApprox(Eigen::RowVector3d(0.005, 0.0025, 0.5)));
  camera.fx = 0;
  EXPECT_THROW(depthToPoints(image, camera), InvalidArgument);
  camera.fx = 100;
  image.depths.pop_back();
  EXPECT_THROW(depthToPoints(image, camera), InvalidArgument);
}

/// A NumPy .npy file (version 1) of `values` as float32, shape `shape`,
/// dtype `descr` as the header says.
std::string npyBytes(const std::string& shape, const std::vector<float>& values,
                     const std::string& descr = "<f4") {
  std::string header =
      "{'descr': '" + descr + "', 'fortran_order': False, 'shape': " + shape + ", }";
  header.resize(118, ' ');  // the data starts at 128 bytes, as numpy aligns it
  header += '\n';
  std::string npy("\x93NUMPY\x01\x00", 8);
  npy += static_cast<char>(header.size() & 0xff);
  npy += static_cast<char>(header.size() >> 8);
  npy += header;
  npy.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
  return npy;
}

/// The field an InvalidArgument from `decode` names, or "none".
template <typename Decode>
std::string refusedField(Decode&& decode) {
  try {
    decode();
  } catch (const InvalidArgument& e) {
    return e.field();
  }
  return "none";
}

TEST(SensorFiles, NpyBytesDecodeToDepthsInMetres) {
  const DepthImage image = decodeDepthNpy(npyBytes("(2, 3)", {0.5f, 1.5f, 0.0f, 2.0f, 2.25f, 3.0f}),
                                          0.001, "npy_base64");
  ASSERT_EQ(image.width, 3);
  ASSERT_EQ(image.height, 2);
  EXPECT_FLOAT_EQ(image.depths[1], 0.0015f);
  EXPECT_FLOAT_EQ(image.depths[4], 0.00225f);  // row 1, column 1
  EXPECT_EQ(image.depths[2], 0.0f);
  EXPECT_EQ(decodeDepthNpy(npyBytes("(1, 1)", {1.25f}), 1.0, "npy_base64").depths[0], 1.25f);
}

TEST(SensorFiles, BadNpyBytesAreRefusedNamingTheField) {
  const std::string good = npyBytes("(2, 2)", {1, 2, 3, 4});
  const auto fieldOf = [](const std::string& bytes) {
    return refusedField([&] { decodeDepthNpy(bytes, 1.0, "npy_base64"); });
  };
  EXPECT_EQ(fieldOf(good), "none");
  EXPECT_EQ(fieldOf(good.substr(0, good.size() - 1)), "npy_base64");  // a value short
  EXPECT_EQ(fieldOf(good.substr(0, 9)), "npy_base64");                // within the length
  EXPECT_EQ(fieldOf(good.substr(0, 60)), "npy_base64");               // within the header
  EXPECT_EQ(fieldOf(""), "npy_base64");
  EXPECT_EQ(fieldOf("\x89PNG\r\n\x1a\n and more"), "npy_base64");  // not a .npy
  EXPECT_EQ(fieldOf(npyBytes("(2, 2)", {1, 2, 3, 4}, "<f8")), "npy_base64");
  EXPECT_EQ(fieldOf(npyBytes("(4,)", {1, 2, 3, 4})), "npy_base64");  // one dimension
  std::string fortran = good;
  fortran.replace(fortran.find("False"), 5, "True ");
  EXPECT_EQ(fieldOf(fortran), "npy_base64");
  try {
    decodeDepthNpy(npyBytes("(2, 2)", {1, 2, 3, 4}, "<i2"), 1.0, "npy_base64");
    ADD_FAILURE() << "int16 accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(std::string(e.what()), "npy_base64: the image: must hold float32 ('<f4'), not '<i2'");
  }
  EXPECT_EQ(refusedField([&] { decodeDepthNpy(good, 0.0, "npy_base64"); }), "scale");
}

class Files : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::temp_directory_path() /
        ("hfts-point-cloud-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write(const std::string& name, const std::string& bytes) {
    std::ofstream(dir_ / name, std::ios::binary) << bytes;
    return dir_ / name;
  }
  /// A 16-bit grey PNG of `values` (row-major).
  fs::path png(const std::string& name, int width, int height,
               const std::vector<std::uint16_t>& values) {
    const fs::path path = dir_ / name;
    std::FILE* file = std::fopen(path.c_str(), "wb");
    png_structp p = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(p);
    png_init_io(p, file);
    png_set_IHDR(p, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 16,
                 PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_write_info(p, info);
    std::vector<png_byte> row(static_cast<std::size_t>(2 * width));
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const std::uint16_t value = values[static_cast<std::size_t>(y * width + x)];
        row[static_cast<std::size_t>(2 * x)] = static_cast<png_byte>(value >> 8);
        row[static_cast<std::size_t>(2 * x + 1)] = static_cast<png_byte>(value & 0xff);
      }
      png_write_row(p, row.data());
    }
    png_write_end(p, nullptr);
    png_destroy_write_struct(&p, &info);
    std::fclose(file);
    return path;
  }
  fs::path dir_;
};

TEST_F(Files, PcdAndPlyCloudsAreRead) {
  const Vertices pcd =
      readPointCloud(write("a.pcd",
                           "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
                           "COUNT 1 1 1\nWIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\n"
                           "POINTS 3\nDATA ascii\n0.1 0.2 0.3\nnan nan nan\n1 2 3\n"));
  ASSERT_EQ(pcd.rows(), 2);  // the NaN point is dropped
  EXPECT_TRUE(pcd.row(1).isApprox(Eigen::RowVector3d(1, 2, 3)));
  const Vertices ply = readPointCloud(
      write("b.ply",
            "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
            "property float z\nend_header\n0.5 0.25 -1\n-2 0 4\n"));
  ASSERT_EQ(ply.rows(), 2);
  EXPECT_TRUE(ply.row(0).isApprox(Eigen::RowVector3d(0.5, 0.25, -1)));
  EXPECT_THROW(readPointCloud(write("c.pcd", "not a cloud")), InvalidArgument);
  EXPECT_THROW(readPointCloud(write("d.xyz", "0 0 0\n")), InvalidArgument);
  EXPECT_THROW(readPointCloud(dir_ / "missing.pcd"), InvalidArgument);
}

TEST_F(Files, CloudsKeepTheirNormalsWhenTheyHaveThem) {
  const SensedPoints pcd = readPointCloudWithNormals(
      write("n.pcd",
            "VERSION .7\nFIELDS x y z normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4\n"
            "TYPE F F F F F F\nCOUNT 1 1 1 1 1 1\nWIDTH 3\nHEIGHT 1\n"
            "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n0.1 0.2 0.3 0 0 1\n"
            "nan nan nan 1 0 0\n1 2 3 nan 0 0\n"));
  ASSERT_EQ(pcd.points.rows(), 2);
  ASSERT_TRUE(pcd.normals.has_value());
  ASSERT_EQ(pcd.normals->rows(), 2);  // one per point kept, in order
  EXPECT_TRUE(pcd.normals->row(0).isApprox(Eigen::RowVector3d(0, 0, 1)));
  EXPECT_TRUE(pcd.normals->row(1).isZero());  // not finite: none
  const SensedPoints ply = readPointCloudWithNormals(
      write("n.ply",
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
            "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
            "end_header\n0.5 0.25 -1 0 -1 0\n"));
  ASSERT_TRUE(ply.normals.has_value());
  EXPECT_TRUE(ply.normals->row(0).isApprox(Eigen::RowVector3d(0, -1, 0)));
  // Without normals in the file, none.
  EXPECT_FALSE(
      readPointCloudWithNormals(write("p.ply",
                                      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                      "property float y\nproperty float z\nend_header\n1 2 3\n"))
          .normals.has_value());
}

TEST_F(Files, DepthImagesAreReadFromPngInTheirUnitsAndFromNpy) {
  const DepthImage mm = readDepthImage(png("d.png", 2, 2, {0, 1000, 65535, 1}), 0.001);
  ASSERT_EQ(mm.width, 2);
  ASSERT_EQ(mm.height, 2);
  EXPECT_EQ(mm.depths[0], 0.0f);
  EXPECT_FLOAT_EQ(mm.depths[1], 1.0f);
  EXPECT_FLOAT_EQ(mm.depths[2], 65.535f);
  EXPECT_FLOAT_EQ(mm.depths[3], 0.001f);
  const std::string npy = npyBytes("(1, 3)", {0.5f, 1.5f, 0.0f});
  const DepthImage m = readDepthImage(write("d.npy", npy), 1.0);
  ASSERT_EQ(m.width, 3);
  ASSERT_EQ(m.height, 1);
  EXPECT_EQ(m.depths[1], 1.5f);
  EXPECT_THROW(readDepthImage(write("e.png", "garbage"), 0.001), InvalidArgument);
  EXPECT_THROW(readDepthImage(write("f.npy", npy.substr(0, npy.size() - 4)), 1.0), InvalidArgument);
  EXPECT_THROW(readDepthImage(write("g.tiff", "x"), 1.0), InvalidArgument);
}

TEST_F(Files, ASceneTakesCloudsAndDepthImagesAsObstacles) {
  png("view.png", 4, 4, std::vector<std::uint16_t>(16, 800));  // a wall 0.8 m ahead
  write("cloud.pcd",
        "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\n"
        "POINTS 2\nDATA ascii\n0 0 0\n0.05 0 0\n");
  const std::string pose = R"("pose": {"position": [0.5, 0, 0.3], "orientation": [0, 0, 0, 1]})";
  auto scene = [&](const std::string& obstacle) {
    return parseScene(
        R"({"name": "s", "robot_base": {"position": [0, 0, 0], "orientation": [0, 0, 0, 1]},
      "obstacles": [)" +
            obstacle + R"(], "target": {"object": "mug", )" + pose + "}}",
        dir_, "test");
  };
  const Scene inline_ =
      scene(R"({"name": "seen", "type": "points", )" + pose +
            R"(, "points": [[0, 0, 0], [0.1, 0, 0]], "voxel": 0.02, "radius": 0})");
  ASSERT_EQ(inline_.obstacles[0].type, Obstacle::Type::kPoints);
  EXPECT_EQ(inline_.obstacles[0].cloud->occupied_count, 2u);
  EXPECT_NEAR(topOf(inline_.obstacles[0]), 0.32, 1e-12);  // voxel [0, 0.02) above z = 0.3
  const Scene file =
      scene(R"({"name": "seen", "type": "points", )" + pose + R"(, "file": "cloud.pcd"})");
  EXPECT_GE(file.obstacles[0].cloud->occupied_count, 2u);
  const Scene depth = scene(R"({"name": "view", "type": "depth_image", )" + pose +
                            R"(, "file": "view.png", "units": "mm",
      "intrinsics": {"fx": 4, "fy": 4, "cx": 1.5, "cy": 1.5}})");
  const VoxelCloud& wall = *depth.obstacles[0].cloud;
  // The same image inline, as a request's inline scene gives it.
  std::ostringstream bytes;
  bytes << std::ifstream(dir_ / "view.png", std::ios::binary).rdbuf();
  const Scene inlined =
      scene(R"({"name": "view", "type": "depth_image", )" + pose + R"(, "png_base64": ")" +
            core::base64Encode(bytes.str()) + R"(", "units": "mm",
      "intrinsics": {"fx": 4, "fy": 4, "cx": 1.5, "cy": 1.5}})");
  EXPECT_EQ(inlined.obstacles[0].cloud->occupied, wall.occupied);
  // And as a float32 .npy in metres.
  const std::string intrinsics = R"("intrinsics": {"fx": 4, "fy": 4, "cx": 1.5, "cy": 1.5})";
  const Scene npy =
      scene(R"({"name": "view", "type": "depth_image", )" + pose + R"(, "npy_base64": ")" +
            core::base64Encode(npyBytes("(4, 4)", std::vector<float>(16, 0.8f))) +
            R"(", "units": "m", )" + intrinsics + "}");
  EXPECT_EQ(npy.obstacles[0].cloud->occupied, wall.occupied);
  EXPECT_NEAR(wall.points.col(2).mean(), 0.8, 0.006);
  EXPECT_GT(wall.occupied_count, 4u);
  auto fieldOf = [&](const std::string& obstacle) {
    try {
      scene(obstacle);
    } catch (const SceneError& e) {
      return e.field();
    }
    return std::string("none");
  };
  EXPECT_EQ(fieldOf(R"({"name": "a", "type": "points", )" + pose + "}"), "obstacles[0]");
  EXPECT_EQ(fieldOf(R"({"name": "a", "type": "points", )" + pose + R"(, "points": [[0, 0]]})"),
            "obstacles[0].points[0]");
  EXPECT_EQ(fieldOf(R"({"name": "a", "type": "points", )" + pose +
                    R"(, "points": [[0, 0, 0]], "voxel": 0})"),
            "obstacles[0].voxel");
  EXPECT_EQ(fieldOf(R"({"name": "a", "type": "points", )" + pose + R"(, "file": "none.pcd"})"),
            "obstacles[0].file");
  EXPECT_EQ(
      fieldOf(
          R"({"name": "a", "type": "depth_image", )" + pose +
          R"(, "file": "view.png", "units": "cm", "intrinsics": {"fx": 4, "fy": 4, "cx": 1, "cy": 1}})"),
      "obstacles[0].units");
  EXPECT_EQ(
      fieldOf(
          R"({"name": "a", "type": "depth_image", )" + pose +
          R"(, "file": "view.png", "units": "mm", "intrinsics": {"fx": 0, "fy": 4, "cx": 1, "cy": 1}})"),
      "obstacles[0].intrinsics.fx");
  EXPECT_EQ(
      fieldOf(
          R"({"name": "a", "type": "depth_image", )" + pose +
          R"(, "file": "view.png", "units": "mm", "max_depth": 0.5, "intrinsics": {"fx": 4, "fy": 4, "cx": 1, "cy": 1}})"),
      "obstacles[0].file");  // every depth beyond max_depth
  EXPECT_EQ(
      fieldOf(
          R"({"name": "a", "type": "depth_image", )" + pose +
          R"(, "png_base64": "%%%", "units": "mm", "intrinsics": {"fx": 4, "fy": 4, "cx": 1, "cy": 1}})"),
      "obstacles[0].png_base64");
  EXPECT_EQ(
      fieldOf(
          R"({"name": "a", "type": "depth_image", )" + pose +
          R"(, "png_base64": "AAAA", "units": "mm", "intrinsics": {"fx": 4, "fy": 4, "cx": 1, "cy": 1}})"),
      "obstacles[0].png_base64");  // not a PNG
  EXPECT_EQ(fieldOf(R"({"name": "a", "type": "depth_image", )" + pose +
                    R"(, "npy_base64": "AAAA", "units": "m", )" + intrinsics + "}"),
            "obstacles[0].npy_base64");  // not a .npy
  EXPECT_EQ(
      fieldOf(R"({"name": "a", "type": "depth_image", )" + pose +
              R"(, "file": "view.png", "npy_base64": "AAAA", "units": "m", )" + intrinsics + "}"),
      "obstacles[0]");  // two images
  EXPECT_EQ(fieldOf(R"({"name": "a", "type": "depth_image", )" + pose + R"(, "units": "m", )" +
                    intrinsics + "}"),
            "obstacles[0]");  // none
}

/// A table and a wall seen as noisy clouds, in front of the KR5.
Scene cloudScene() {
  std::mt19937_64 rng(17);
  Scene scene;
  scene.name = "clouds";
  Obstacle table;
  table.name = "table";
  table.type = Obstacle::Type::kPoints;
  table.pose.translation() = Eigen::Vector3d(0.6, 0.0, 0.25);
  auto cloud = std::make_shared<VoxelCloud>(
      voxelize(noisyBox({0, 0, 0}, {0.5, 0.8, 0.04}, 30000, 0.003, rng), CloudOptions{}));
  table.cloud = cloud;
  table.mesh = cloud->mesh;
  table.distance_grid = std::shared_ptr<const db::DistanceGrid>(cloud, &cloud->distances);
  scene.obstacles.push_back(table);
  Obstacle wall = table;
  wall.name = "wall";
  wall.pose = Eigen::Isometry3d(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()));
  wall.pose.translation() = Eigen::Vector3d(0.2, 0.55, 0.5);
  cloud = std::make_shared<VoxelCloud>(
      voxelize(noisyBox({0, 0, 0}, {0.6, 0.03, 0.8}, 30000, 0.003, rng), CloudOptions{}));
  wall.cloud = cloud;
  wall.mesh = cloud->mesh;
  wall.distance_grid = std::shared_ptr<const db::DistanceGrid>(cloud, &cloud->distances);
  scene.obstacles.push_back(wall);
  return scene;
}

TEST(PointCloudScene, TheTwoTiersAgreeWithFclAloneOnRandomConfigurations) {
  const RobotModel& model = test::kr5Sdh();
  const Scene scene = cloudScene();
  CollisionChecker tiers(test::collisionOf(model), scene, nullptr);
  CollisionChecker fcl(test::collisionOf(model), scene, nullptr);
  fcl.setSphereTier(false);
  std::mt19937_64 rng(23);
  int colliding = 0, disagreements = 0;
  const int n = 10000;
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd q(model.numDofs());
    for (int d = 0; d < model.numDofs(); ++d) {
      std::uniform_real_distribution<double> u(model.lowerLimits()(d), model.upperLimits()(d));
      q(d) = u(rng);
    }
    const CollisionRequest onlyObstacles = CollisionRequest::obstaclesOnly();
    const bool a = tiers.inCollision(q, onlyObstacles), b = fcl.inCollision(q, onlyObstacles);
    colliding += b ? 1 : 0;
    disagreements += a != b ? 1 : 0;
  }
  EXPECT_EQ(disagreements, 0);
  EXPECT_GT(colliding, n / 20);  // the clouds are in the way of many
  EXPECT_LT(colliding, n * 19 / 20);
  EXPECT_GT(tiers.sphereSettledCount(), static_cast<std::uint64_t>(n / 10));
}

TEST(PointCloudScene, ASphereTouchesTheCloudWhereItsVoxelsAre) {
  const RobotModel& model = test::kr5Sdh();
  const Scene scene = cloudScene();
  const CollisionScene collision(test::collisionOf(model), scene, nullptr);
  for (const Obstacle& o : scene.obstacles) {
    // Above the middle of the highest run of voxels (the cloud's frame's z).
    const auto boxes = o.cloud->boxes();
    const auto highest = std::max_element(
        boxes.begin(), boxes.end(), [](auto& a, auto& b) { return a.first.z() < b.first.z(); });
    const Eigen::Vector3d up = o.pose.linear().col(2);
    const Eigen::Vector3d top =
        o.pose * (highest->first + Eigen::Vector3d(0, 0, 0.5 * highest->second.z()));
    EXPECT_TRUE(collision.sphereTouchesObstacles(top + 0.004 * up, 0.005)) << o.name;
    EXPECT_FALSE(collision.sphereTouchesObstacles(top + 0.006 * up, 0.005)) << o.name;
  }
}

/// A 6 cm cube standing on z = 0 (its frame), with its distance grid.
db::ObjectGeometry cubeGeometry() {
  TriangleMesh m;
  m.vertices.resize(8, 3);
  for (int c = 0; c < 8; ++c)
    m.vertices.row(c) << ((c & 1) ? 0.03 : -0.03), ((c & 2) ? 0.03 : -0.03), ((c & 4) ? 0.06 : 0.0);
  m.triangles.resize(12, 3);
  m.triangles << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2,
      4, 6, 1, 3, 5, 3, 7, 5;
  db::ObjectGeometry cube;
  cube.mesh_vertices = m.vertices;
  cube.mesh_triangles = m.triangles;
  cube.distance_grid = db::buildDistanceGrid(m, true);
  return cube;
}

TEST(PointCloudScene, TheTargetIsCarvedOutOfTheCloudItStandsIn) {
  // A 6 cm cube standing on a table seen as a noisy cloud: the cloud's
  // voxels reach into the cube's bottom (noise, radius, voxels).
  Scene scene = cloudScene();
  const Obstacle& table = scene.obstacles[0];
  const db::ObjectGeometry cube = cubeGeometry();
  scene.target_object = "cube";
  scene.target_pose = Eigen::Isometry3d::Identity();
  scene.target_pose.translation() = Eigen::Vector3d(0.6, 0.0, 0.25 + 0.02);  // on the table's top
  const RobotModel& model = test::kr5Sdh();
  ASSERT_TRUE(CollisionScene(test::collisionOf(model), scene, &cube).targetTouchesObstacles());
  const Scene carved = withTargetCarved(scene, cube.distance_grid, cube.mesh_vertices);
  EXPECT_FALSE(CollisionScene(test::collisionOf(model), carved, &cube).targetTouchesObstacles());
  // Only voxels near the cube went; the wall, far from it, is shared as it was.
  const std::size_t removed =
      table.cloud->occupied_count - carved.obstacles[0].cloud->occupied_count;
  EXPECT_GT(removed, 0u);
  EXPECT_LT(removed, 400u);  // the cube's footprint and a ring (8 x 8 cm), three layers at most
  EXPECT_EQ(carved.obstacles[1].cloud, scene.obstacles[1].cloud);
}

TEST(PointCloudScene, TheRobotAtItsStartIsCarvedOutOfTheCloud) {
  // A camera sees the robot as well: points on its links at home join the
  // table's, as they would in a depth image of the cell.
  const RobotModel& model = test::kr5Sdh();
  Scene scene = cloudScene();
  const LinkPoses poses = forwardKinematics(model, model.home());
  std::mt19937_64 rng(31);
  std::vector<Eigen::Vector3d> seen;
  for (std::size_t l = 0; l < model.links().size(); ++l)
    for (const CollisionShape& shape : model.links()[l].shapes)
      if (shape.type == CollisionShape::Type::kBox || shape.type == CollisionShape::Type::kCylinder)
        for (int i = 0; i < 200; ++i) {  // points inside the shape's box: on or in the link
          const Eigen::Vector3d half =
              shape.type == CollisionShape::Type::kBox
                  ? Eigen::Vector3d(shape.size / 2)
                  : Eigen::Vector3d(shape.size.x() / 2, shape.size.x() / 2, shape.size.y() / 2);
          std::uniform_real_distribution<double> u(-1.0, 1.0);
          seen.push_back(poses[l] * shape.origin *
                         Eigen::Vector3d(u(rng) * half.x(), u(rng) * half.y(), u(rng) * half.z()));
        }
  Vertices points(static_cast<Eigen::Index>(seen.size()), 3);
  for (std::size_t i = 0; i < seen.size(); ++i)
    points.row(static_cast<Eigen::Index>(i)) = seen[i].transpose();
  Obstacle robotSeen = scene.obstacles[0];
  robotSeen.name = "robot_seen";
  robotSeen.pose = Eigen::Isometry3d::Identity();
  auto cloud = std::make_shared<VoxelCloud>(voxelize(points, CloudOptions{}));
  robotSeen.cloud = cloud;
  robotSeen.mesh = cloud->mesh;
  robotSeen.distance_grid = std::shared_ptr<const db::DistanceGrid>(cloud, &cloud->distances);
  scene.obstacles.push_back(robotSeen);
  CollisionChecker before(test::collisionOf(model), scene, nullptr);
  CollisionPair pair;
  ASSERT_TRUE(before.inCollision(model.home(), CollisionRequest::obstaclesOnly(), &pair));
  const Scene carved = withRobotCarved(scene, model, model.home());
  CollisionChecker after(test::collisionOf(model), carved, nullptr);
  EXPECT_FALSE(after.inCollision(model.home(), CollisionRequest::obstaclesOnly(), &pair))
      << pair.first << " touches " << pair.second;
  // The robot's own voxels went (the cloud with them); the table stays.
  ASSERT_EQ(carved.obstacles.size(), 2u);
  EXPECT_EQ(carved.obstacles[0].cloud->occupied_count, scene.obstacles[0].cloud->occupied_count);
}

/// A cloud obstacle of `points` (world frame) seen from `eye`, with shadows.
Obstacle viewObstacle(const std::string& name, const Vertices& points, const Eigen::Vector3d& eye) {
  Obstacle o;
  o.name = name;
  o.type = Obstacle::Type::kPoints;
  CloudOptions options;
  options.viewpoint = eye;
  options.shadow = 0.5;
  auto cloud = std::make_shared<VoxelCloud>(voxelize(points, options));
  o.cloud = cloud;
  o.mesh = cloud->mesh;
  o.distance_grid = std::shared_ptr<const db::DistanceGrid>(cloud, &cloud->distances);
  return o;
}

/// Points on the plane x = `x`, |y|, |z| <= `half`, `spacing` apart.
Vertices wallAt(double x, double half, double spacing) {
  std::vector<Eigen::Vector3d> points;
  for (double y = -half; y <= half + 1e-9; y += spacing)
    for (double z = -half; z <= half + 1e-9; z += spacing) points.emplace_back(x, y, z);
  Vertices out(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    out.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
  return out;
}

/// Camera A sees a wall at x = 1 and leaves 0.5 m of shadow behind it;
/// camera B, beside it, looks across that shadow at a wall of its own.
Scene twoWalls() {
  Scene scene;
  scene.obstacles.push_back(viewObstacle("a", wallAt(1.0, 0.1, 0.005), {0, 0, 0}));
  Vertices across = wallAt(0.0, 0.1, 0.005);
  for (Eigen::Index i = 0; i < across.rows(); ++i)
    across.row(i) = Eigen::Vector3d(1.25 + across(i, 2), -1.0, across(i, 1)).transpose();
  scene.obstacles.push_back(viewObstacle("b", across, {1.25, 2.0, 0.0}));
  return scene;
}

TEST(SensedScene, AnotherViewClearsTheShadowsItSawThrough) {
  Scene scene = twoWalls();
  const VoxelCloud& a = *scene.obstacles[0].cloud;
  ASSERT_TRUE(a.isOccupied(125, 0, 0));  // in A's shadow: x = 1.25
  const Scene fused = withSeenSpaceCarved(scene);
  ASSERT_EQ(fused.obstacles.size(), 2u);
  const VoxelCloud& carvedA = *fused.obstacles[0].cloud;
  EXPECT_LT(carvedA.occupied_count, a.occupied_count);
  EXPECT_FALSE(carvedA.isOccupied(125, 0, 0));  // B saw through it
  EXPECT_TRUE(carvedA.isOccupied(100, 0, 0));   // A's wall itself stays
  EXPECT_TRUE(carvedA.isOccupied(149, 0, 0));   // beyond B's rays (x 1.15 .. 1.35)
  // B's own wall is seen by B: it stays whole (A's rays end at x = 1).
  EXPECT_EQ(fused.obstacles[1].cloud->occupied_count, scene.obstacles[1].cloud->occupied_count);
  // One view alone clears nothing.
  Scene one;
  one.obstacles.push_back(scene.obstacles[0]);
  EXPECT_EQ(withSeenSpaceCarved(one).obstacles[0].cloud->occupied_count, a.occupied_count);
}

TEST(SensedScene, TheHiddenSideOfAnObjectFromViewsIsAnObstacle) {
  Scene scene;
  scene.target_object = "seen";
  scene.target_pose.translation() = Eigen::Vector3d(0.5, 0.0, 0.1);
  // Two boxes of 3 mm voxels: 4 x 10 x 7 and 10 x 4 x 1.
  db::PartialView view;
  view.hidden_voxel = 0.003;
  view.hidden_low.resize(2, 3);
  view.hidden_high.resize(2, 3);
  view.hidden_low << 0.0, 0.0, 0.0, 0.021, -0.012, 0.0;
  view.hidden_high << 0.012, 0.03, 0.021, 0.051, 0.0, 0.003;
  db::ObjectDatabase fromViews;
  fromViews.partial_view = view;
  const Scene out = withHiddenSide(scene, fromViews);
  ASSERT_EQ(out.obstacles.size(), 1u);
  const Obstacle& hidden = out.obstacles[0];
  EXPECT_EQ(hidden.name, "seen.hidden");
  EXPECT_EQ(hidden.name, hiddenSideName("seen"));
  ASSERT_EQ(hidden.type, Obstacle::Type::kPoints);
  EXPECT_TRUE(hidden.pose.isApprox(scene.target_pose));
  // Exactly the boxes' voxels (obstacle frame), none around them.
  const VoxelCloud& cloud = *hidden.cloud;
  EXPECT_EQ(cloud.occupied_count, 4u * 10u * 7u + 10u * 4u * 1u);
  EXPECT_TRUE(cloud.isOccupied(0, 0, 0));
  EXPECT_TRUE(cloud.isOccupied(3, 9, 6));
  EXPECT_FALSE(cloud.isOccupied(4, 0, 0));
  EXPECT_TRUE(cloud.isOccupied(7, -4, 0));
  EXPECT_FALSE(cloud.isOccupied(7, -4, 1));
  EXPECT_TRUE(cloud.low().isApprox(Eigen::Vector3d(0.0, -0.012, 0.0)));
  EXPECT_TRUE(cloud.high().isApprox(Eigen::Vector3d(0.051, 0.03, 0.021)));
  // No boxes: the scene as it is.
  EXPECT_TRUE(withHiddenSide(scene, db::ObjectDatabase{}).obstacles.empty());
  // The planner's scene has it for an object from views, and not for one
  // from a mesh (its target carving needs a mesh: none here).
  const RobotModel& model = test::kr5Sdh();
  const Scene planned = asPlannerSees(scene, fromViews, model, model.home());
  ASSERT_EQ(planned.obstacles.size(), 1u);
  EXPECT_EQ(planned.obstacles[0].name, "seen.hidden");
  EXPECT_TRUE(asPlannerSees(scene, db::ObjectDatabase{}, model, model.home()).obstacles.empty());
}

/// The 6 cm cube as if known from views, with hidden boxes of 3 mm voxels
/// from `low` to `high` (its frame).
db::ObjectDatabase cubeFromViews(const Vertices& low, const Vertices& high) {
  db::ObjectDatabase target;
  target.geometry = cubeGeometry();
  db::PartialView& view = target.partial_view.emplace();
  view.hidden_voxel = 0.003;
  view.hidden_low = low;
  view.hidden_high = high;
  return target;
}

TEST(SensedScene, HiddenSpaceTouchingTheObjectGoesWithItWhenHeld) {
  // A 6 cm cube known from views; hidden space beside it: a slab of 3 mm
  // voxels against its +x face (overlapping it by half a voxel) and a
  // column 3 cm away from it.
  Scene scene;
  scene.target_object = "seen";
  scene.target_pose.translation() = Eigen::Vector3d(0.5, 0.0, 0.1);
  Vertices low(2, 3), high(2, 3);
  low << 0.027, -0.03, 0.0, 0.06, -0.003, 0.0;
  high << 0.033, 0.03, 0.06, 0.066, 0.003, 0.06;
  const db::ObjectDatabase target = cubeFromViews(low, high);
  const Scene planned = withHiddenSide(scene, target);
  ASSERT_EQ(planned.obstacles.size(), 2u);
  const Obstacle& apart = planned.obstacles[0];
  const Obstacle& skin = planned.obstacles[1];
  EXPECT_EQ(apart.name, hiddenSideName("seen"));
  EXPECT_EQ(skin.name, hiddenSkinName("seen"));
  // Both voxel layers of the slab touch the cube (their centres 1.5 and
  // 4.5 mm from its face, within half a diagonal, 2.6 mm, plus the grid's
  // bound); the column, 3 cm away, does not.
  EXPECT_EQ(skin.cloud->occupied_count + apart.cloud->occupied_count,
            2u * 20u * 20u + 2u * 2u * 20u);
  EXPECT_GE(skin.cloud->occupied_count, 20u * 20u);
  EXPECT_TRUE(skin.cloud->isOccupied(9, 0, 0));    // the slab's first layer, x in [27, 30] mm
  EXPECT_TRUE(apart.cloud->isOccupied(20, 0, 0));  // the column, x in [60, 63] mm
  EXPECT_FALSE(skin.cloud->isOccupied(20, 0, 0));
  // Both are beside the target: it may touch them.
  const RobotModel& model = test::kr5Sdh();
  EXPECT_FALSE(
      CollisionScene(test::collisionOf(model), planned, &target.geometry).targetTouchesObstacles());
  // Held, the object takes the skin with it; the rest stays an obstacle.
  const Scene held = heldScene(planned);
  EXPECT_TRUE(held.target_object.empty());
  ASSERT_EQ(held.obstacles.size(), 1u);
  EXPECT_EQ(held.obstacles[0].name, hiddenSideName("seen"));
}

TEST(SensedScene, ThePlannersSceneIsTheCarvingsOneAfterTheOther) {
  // Two views (the shadows of one seen through by the other), a 6 cm cube
  // known from views standing in the first view's wall, its hidden space
  // beside it, and the robot at home: asPlannerSees carves each cloud once,
  // with the same voxels as the carvings in turn.
  Scene scene = twoWalls();
  scene.target_object = "seen";
  scene.target_pose.translation() = Eigen::Vector3d(1.0, 0.0, -0.03);
  Vertices low(1, 3), high(1, 3);
  low << 0.027, -0.03, 0.0;
  high << 0.06, 0.03, 0.06;
  const db::ObjectDatabase target = cubeFromViews(low, high);
  const RobotModel& model = test::kr5Sdh();
  const Scene once = asPlannerSees(scene, target, model, model.home());
  const Scene inTurn = withRobotCarved(
      withHiddenSide(withTargetCarved(withSeenSpaceCarved(scene), target.geometry.distance_grid,
                                      target.geometry.mesh_vertices),
                     target),
      model, model.home());
  ASSERT_EQ(once.obstacles.size(), inTurn.obstacles.size());
  ASSERT_EQ(once.obstacles.size(), 4u);
  for (std::size_t o = 0; o < once.obstacles.size(); ++o) {
    EXPECT_EQ(once.obstacles[o].name, inTurn.obstacles[o].name);
    EXPECT_EQ(once.obstacles[o].cloud->occupied, inTurn.obstacles[o].cloud->occupied);
    EXPECT_EQ(once.obstacles[o].cloud->points, inTurn.obstacles[o].cloud->points);
  }
  // Each carving took something: the shadow, the cube's voxels in the wall.
  EXPECT_LT(once.obstacles[0].cloud->occupied_count, scene.obstacles[0].cloud->occupied_count);
}

}  // namespace
}  // namespace hfts::robot
