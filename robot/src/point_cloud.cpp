#include "robot/point_cloud.h"

#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "core/invalid_argument.h"

namespace hfts::robot {
namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

/// Voxels further than this (along one axis, in voxels) from an occupied
/// one get a distance bound of (kWindow + 1/2) voxels instead of their own:
/// the distance grid's passes look this far.
constexpr int kWindow = 8;
/// Voxel indices stay within octomap's keys (16 bits around 2^15).
constexpr double kMaxVoxelIndex = 32000.0;

[[noreturn]] void fail(const std::string& field, const std::string& problem) {
  throw InvalidArgument(field, problem);
}

Cloud toCloud(const Vertices& points) {
  Cloud cloud;
  cloud.reserve(static_cast<std::size_t>(points.rows()));
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    if (points.row(i).allFinite())
      cloud.push_back(pcl::PointXYZ(static_cast<float>(points(i, 0)),
                                    static_cast<float>(points(i, 1)),
                                    static_cast<float>(points(i, 2))));
  return cloud;
}

Vertices toVertices(const Cloud& cloud) {
  Vertices out(static_cast<Eigen::Index>(cloud.size()), 3);
  for (std::size_t i = 0; i < cloud.size(); ++i)
    out.row(static_cast<Eigen::Index>(i)) << static_cast<double>(cloud[i].x),
        static_cast<double>(cloud[i].y), static_cast<double>(cloud[i].z);
  return out;
}

/// The finite points of `points` in double precision (PCL's are float).
Vertices finiteRows(const Vertices& points) {
  Vertices out(points.rows(), 3);
  Eigen::Index n = 0;
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    if (points.row(i).allFinite()) out.row(n++) = points.row(i);
  out.conservativeResize(n, 3);
  return out;
}

/// Squared distance from p to the voxel [i v, (i + 1) v] along one axis.
double axisGap(double p, int i, double v) {
  const double low = i * v, high = (i + 1) * v;
  const double gap = p < low ? low - p : p > high ? p - high : 0.0;
  return gap * gap;
}

/// One pass of the distance grid (docs/point_clouds.md): along `axis`,
/// f(x) = min over |k| <= kWindow of g(k) + f(x + k), g(k) = max(|k| -
/// 1/2, 0)^2 (squared voxels from a voxel's centre to a voxel k away),
/// and at most g(kWindow + 1), a lower bound of everything further away.
void minPlusPass(std::vector<double>& f, const std::array<int, 3>& dims, int axis) {
  const std::size_t stride = axis == 0   ? 1
                             : axis == 1 ? std::size_t(dims[0])
                                         : std::size_t(dims[0]) * dims[1];
  const int n = dims[static_cast<std::size_t>(axis)];
  double g[kWindow + 2];
  for (int k = 0; k <= kWindow + 1; ++k) g[k] = k == 0 ? 0.0 : (k - 0.5) * (k - 0.5);
  std::vector<double> line(static_cast<std::size_t>(n));
  const std::size_t total = f.size();
  for (std::size_t start = 0; start < total; ++start) {
    // `start` is the first cell of a line when its coordinate along `axis` is 0.
    if ((start / stride) % static_cast<std::size_t>(n) != 0) continue;
    for (int x = 0; x < n; ++x) line[static_cast<std::size_t>(x)] = f[start + x * stride];
    for (int x = 0; x < n; ++x) {
      double best = g[kWindow + 1];
      for (int k = std::max(-kWindow, -x); k <= std::min(kWindow, n - 1 - x); ++k)
        best = std::min(best, g[std::abs(k)] + line[static_cast<std::size_t>(x + k)]);
      f[start + x * stride] = best;
    }
  }
}

float roundedDown(double value) {
  float f = static_cast<float>(value);
  if (static_cast<double>(f) > value)
    f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

/// The grid at the centres of the block's voxels and a border of one.
db::DistanceGrid distanceGrid(const VoxelCloud& cloud) {
  const double v = cloud.options.voxel;
  const std::array<int, 3> dims{cloud.dims[0] + 2, cloud.dims[1] + 2, cloud.dims[2] + 2};
  std::vector<double> f(static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]) *
                            static_cast<std::size_t>(dims[2]),
                        std::numeric_limits<double>::infinity());
  for (int z = 0; z < cloud.dims[2]; ++z)
    for (int y = 0; y < cloud.dims[1]; ++y)
      for (int x = 0; x < cloud.dims[0]; ++x)
        if (cloud.occupied[std::size_t(x) +
                           std::size_t(cloud.dims[0]) * (y + std::size_t(cloud.dims[1]) * z)])
          f[std::size_t(x + 1) + std::size_t(dims[0]) * (y + 1 + std::size_t(dims[1]) * (z + 1))] =
              0.0;
  for (int axis = 0; axis < 3; ++axis) minPlusPass(f, dims, axis);
  db::DistanceGrid grid;
  for (int a = 0; a < 3; ++a) {
    grid.origin[a] = (cloud.first[static_cast<std::size_t>(a)] - 1 + 0.5) * v;
    grid.dims[static_cast<std::size_t>(a)] =
        static_cast<std::uint32_t>(dims[static_cast<std::size_t>(a)]);
  }
  grid.spacing = v;
  grid.is_signed = false;
  grid.values.resize(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) grid.values[i] = roundedDown(v * std::sqrt(f[i]));
  grid.boundary_min = db::boundaryMinimum(grid);
  return grid;
}

TriangleMesh boxesMesh(const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& boxes) {
  static const int kFaces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6},
                                    {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7},
                                    {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  TriangleMesh mesh;
  mesh.vertices.resize(static_cast<Eigen::Index>(8 * boxes.size()), 3);
  mesh.triangles.resize(static_cast<Eigen::Index>(12 * boxes.size()), 3);
  for (std::size_t b = 0; b < boxes.size(); ++b) {
    const auto base = static_cast<Eigen::Index>(8 * b);
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d sign((c & 1) ? 0.5 : -0.5, (c & 2) ? 0.5 : -0.5, (c & 4) ? 0.5 : -0.5);
      mesh.vertices.row(base + c) =
          (boxes[b].first + sign.cwiseProduct(boxes[b].second)).transpose();
    }
    for (int t = 0; t < 12; ++t)
      for (int k = 0; k < 3; ++k)
        mesh.triangles(static_cast<Eigen::Index>(12 * b) + t, k) =
            static_cast<std::uint32_t>(base + kFaces[t][k]);
  }
  return mesh;
}

void checkOptions(const CloudOptions& o) {
  if (!std::isfinite(o.voxel) || o.voxel < 0.001 || o.voxel > 1.0)
    fail("voxel", "must be a voxel edge from 0.001 to 1 m, not " + std::to_string(o.voxel));
  if (!std::isfinite(o.radius) || o.radius < 0.0 || o.radius > 10 * o.voxel)
    fail("radius", "must be from 0 to ten voxels (m), not " + std::to_string(o.radius));
  if (!std::isfinite(o.shadow) || o.shadow < 0.0 || o.shadow > 2.0)
    fail("shadow", "must be from 0 to 2 m, not " + std::to_string(o.shadow));
  if (o.viewpoint && !o.viewpoint->allFinite()) fail("viewpoint", "must be finite");
  if (o.remove_outliers && (o.outlier_neighbours < 1 || o.outlier_neighbours > 1000 ||
                            !std::isfinite(o.outlier_stddev) || o.outlier_stddev <= 0.0))
    fail("outliers", "needs 1 to 1000 neighbours and a positive number of standard deviations");
}

}  // namespace

Eigen::Vector3d VoxelCloud::low() const {
  return Eigen::Vector3d(first[0], first[1], first[2]) * options.voxel;
}

Eigen::Vector3d VoxelCloud::high() const {
  return Eigen::Vector3d(first[0] + dims[0], first[1] + dims[1], first[2] + dims[2]) *
         options.voxel;
}

bool VoxelCloud::isOccupied(int i, int j, int k) const {
  const int x = i - first[0], y = j - first[1], z = k - first[2];
  if (x < 0 || y < 0 || z < 0 || x >= dims[0] || y >= dims[1] || z >= dims[2]) return false;
  return occupied[std::size_t(x) + std::size_t(dims[0]) * (y + std::size_t(dims[1]) * z)] != 0;
}

std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> VoxelCloud::boxes() const {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> out;
  const double v = options.voxel;
  for (int z = 0; z < dims[2]; ++z)
    for (int y = 0; y < dims[1]; ++y)
      for (int x = 0; x < dims[0];) {
        if (!isOccupied(first[0] + x, first[1] + y, first[2] + z)) {
          ++x;
          continue;
        }
        int end = x;
        while (end < dims[0] && isOccupied(first[0] + end, first[1] + y, first[2] + z)) ++end;
        const Eigen::Vector3d centre((first[0] + 0.5 * (x + end)) * v, (first[1] + y + 0.5) * v,
                                     (first[2] + z + 0.5) * v);
        out.emplace_back(centre, Eigen::Vector3d((end - x) * v, v, v));
        x = end;
      }
  return out;
}

Vertices depthToPoints(const DepthImage& image, const DepthCamera& camera,
                       const std::vector<std::uint8_t>* mask) {
  for (const double value : {camera.fx, camera.fy})
    if (!std::isfinite(value) || value <= 0.0)
      fail("intrinsics", "needs positive focal lengths fx and fy (pixels)");
  if (!std::isfinite(camera.cx) || !std::isfinite(camera.cy))
    fail("intrinsics", "needs a finite principal point cx, cy (pixels)");
  if (!(camera.min_depth >= 0.0) || !(camera.max_depth > camera.min_depth) ||
      !std::isfinite(camera.max_depth))
    fail("intrinsics", "needs 0 <= min_depth < max_depth (m)");
  if (image.width <= 0 || image.height <= 0 ||
      image.depths.size() != std::size_t(image.width) * std::size_t(image.height))
    fail("image", "has " + std::to_string(image.depths.size()) + " depths for " +
                      std::to_string(image.width) + " x " + std::to_string(image.height) +
                      " pixels");
  if (mask != nullptr && mask->size() != image.depths.size())
    fail("mask", "has " + std::to_string(mask->size()) + " pixels, the depth image " +
                     std::to_string(image.depths.size()));
  Vertices points(static_cast<Eigen::Index>(image.depths.size()), 3);
  Eigen::Index n = 0;
  for (int v = 0; v < image.height; ++v)
    for (int u = 0; u < image.width; ++u) {
      const std::size_t pixel = std::size_t(v) * std::size_t(image.width) + std::size_t(u);
      if (mask != nullptr && (*mask)[pixel] != 0) continue;
      const auto z = static_cast<double>(image.depths[pixel]);
      if (!std::isfinite(z) || z <= 0.0 || z < camera.min_depth || z > camera.max_depth) continue;
      points.row(n++) << (u - camera.cx) * z / camera.fx, (v - camera.cy) * z / camera.fy, z;
    }
  points.conservativeResize(n, 3);
  return points;
}

VoxelCloud withoutVoxels(const VoxelCloud& cloud,
                         const std::function<bool(int i, int j, int k)>& remove) {
  VoxelCloud out = cloud;
  const double v = cloud.options.voxel;
  for (int z = 0; z < cloud.dims[2]; ++z)
    for (int y = 0; y < cloud.dims[1]; ++y)
      for (int x = 0; x < cloud.dims[0]; ++x) {
        std::uint8_t& cell =
            out.occupied[std::size_t(x) +
                         std::size_t(cloud.dims[0]) * (y + std::size_t(cloud.dims[1]) * z)];
        if (cell != 0 && remove(cloud.first[0] + x, cloud.first[1] + y, cloud.first[2] + z)) {
          cell = 0;
          --out.occupied_count;
        }
      }
  if (out.occupied_count == cloud.occupied_count) return out;
  Eigen::Index kept = 0;
  for (Eigen::Index p = 0; p < cloud.points.rows(); ++p) {
    const Eigen::Array3d index = (cloud.points.row(p).transpose().array() / v).floor();
    if (out.isOccupied(static_cast<int>(index.x()), static_cast<int>(index.y()),
                       static_cast<int>(index.z())))
      out.points.row(kept++) = cloud.points.row(p);
  }
  out.points.conservativeResize(kept, 3);
  out.distances = out.occupied_count > 0 ? distanceGrid(out) : db::DistanceGrid{};
  out.mesh = boxesMesh(out.boxes());
  return out;
}

VoxelCloud voxelize(const Vertices& input, const CloudOptions& options) {
  checkOptions(options);
  VoxelCloud cloud;
  cloud.options = options;
  Vertices points = finiteRows(input);
  if (points.rows() == 0) fail("points", "holds no finite point");
  if (options.remove_outliers) {
    pcl::StatisticalOutlierRemoval<pcl::PointXYZ> filter;
    const Cloud::Ptr raw(new Cloud(toCloud(points)));
    filter.setInputCloud(raw);
    filter.setMeanK(options.outlier_neighbours);
    filter.setStddevMulThresh(options.outlier_stddev);
    std::vector<int> kept;
    filter.filter(kept);
    Vertices survivors(static_cast<Eigen::Index>(kept.size()), 3);
    for (std::size_t i = 0; i < kept.size(); ++i)
      survivors.row(static_cast<Eigen::Index>(i)) = points.row(kept[i]);
    points = std::move(survivors);
    if (points.rows() == 0) fail("points", "no point is left after outlier removal");
  }
  const double v = options.voxel;
  const bool shadowed = options.viewpoint && options.shadow > 0.0;
  // With shadows every mark is at least a quarter voxel wide, so the marks
  // half a voxel apart along a ray leave no gap.
  const double r = shadowed ? std::max(options.radius, v / 4) : options.radius;
  Eigen::Vector3d low = points.colwise().minCoeff(), high = points.colwise().maxCoeff();
  if (shadowed)
    for (Eigen::Index p = 0; p < points.rows(); ++p) {
      const Eigen::Vector3d point = points.row(p).transpose();
      const Eigen::Vector3d end =
          point + options.shadow * (point - *options.viewpoint).normalized();
      low = low.cwiseMin(end);
      high = high.cwiseMax(end);
    }
  if ((low.array().abs() / v > kMaxVoxelIndex).any() ||
      (high.array().abs() / v > kMaxVoxelIndex).any())
    fail("points", "lie more than 32000 voxels from the obstacle's origin");
  std::uint64_t voxels = 1;
  for (int a = 0; a < 3; ++a) {
    const std::size_t k = static_cast<std::size_t>(a);
    cloud.first[k] = static_cast<int>(std::floor((low[a] - r) / v));
    cloud.dims[k] = static_cast<int>(std::floor((high[a] + r) / v)) - cloud.first[k] + 1;
    voxels *= static_cast<std::uint64_t>(cloud.dims[k] + 2);
  }
  if (voxels > kMaxCloudVoxels)
    fail("points", "span " + std::to_string(voxels) + " voxels of " + std::to_string(v) +
                       " m, more than " + std::to_string(kMaxCloudVoxels) +
                       ": crop the cloud (max_depth) or choose a coarser voxel");
  cloud.occupied.assign(std::size_t(cloud.dims[0]) * cloud.dims[1] * cloud.dims[2], 0);
  // Every voxel within r of the point: occupied.
  auto mark = [&](const Eigen::Vector3d& point) {
    int from[3], to[3];
    for (int a = 0; a < 3; ++a) {
      from[a] = static_cast<int>(std::floor((point[a] - r) / v));
      to[a] = static_cast<int>(std::floor((point[a] + r) / v));
    }
    for (int k = from[2]; k <= to[2]; ++k)
      for (int j = from[1]; j <= to[1]; ++j)
        for (int i = from[0]; i <= to[0]; ++i) {
          const double gap =
              axisGap(point.x(), i, v) + axisGap(point.y(), j, v) + axisGap(point.z(), k, v);
          if (gap > r * r) continue;
          std::uint8_t& cell =
              cloud.occupied[std::size_t(i - cloud.first[0]) +
                             std::size_t(cloud.dims[0]) *
                                 (std::size_t(j - cloud.first[1]) +
                                  std::size_t(cloud.dims[1]) * std::size_t(k - cloud.first[2]))];
          cloud.occupied_count += cell == 0 ? 1 : 0;
          cell = 1;
        }
  };
  // Behind each point, as the sensor looks, up to the shadow's length: half
  // a voxel apart, each with the radius (at least a quarter voxel: no gap).
  const double step = v / 2;
  for (Eigen::Index p = 0; p < points.rows(); ++p) {
    const Eigen::Vector3d point = points.row(p).transpose();
    mark(point);
    if (!shadowed) continue;
    const Eigen::Vector3d along = (point - *options.viewpoint).normalized();
    for (double t = step; t < options.shadow + step / 2; t += step) mark(point + t * along);
  }
  cloud.distances = distanceGrid(cloud);
  cloud.mesh = boxesMesh(cloud.boxes());
  // The points kept for drawing: PCL's voxel grid at half a voxel.
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  const Cloud::Ptr raw(new Cloud(toCloud(points)));
  grid.setInputCloud(raw);
  const float leaf = static_cast<float>(v / 2);
  grid.setLeafSize(leaf, leaf, leaf);
  Cloud drawn;
  grid.filter(drawn);
  cloud.points = toVertices(drawn);
  return cloud;
}

}  // namespace hfts::robot
