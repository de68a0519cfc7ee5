// carveViews (preprocess/partial_view.h): where an object seen by depth
// cameras may be, as the voxels no camera saw through.
#include <pcl/console/print.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/ransac.h>
#include <pcl/sample_consensus/sac_model_perpendicular_plane.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <string>

#include "core/invalid_argument.h"
#include "preprocess/partial_view.h"

namespace hfts::preprocess {
namespace {

constexpr double kFinestVoxel = 0.003;
constexpr double kMostVoxels = 8e6;
/// Planes of fewer inliers are not taken for the support.
constexpr std::size_t kLeastSupportInliers = 50;
/// How far from horizontal a support may be (rad).
constexpr double kSupportTilt = 10.0 * 3.14159265358979323846 / 180.0;

bool hasReading(float depth) {
  return std::isfinite(depth) && depth > 0.0f;
}

void checkEvidence(const DepthEvidence& view, std::size_t index) {
  const std::string which = "view " + std::to_string(index) + ": ";
  if (view.width <= 0 || view.height <= 0 ||
      view.depths.size() != std::size_t(view.width) * std::size_t(view.height))
    throw InvalidArgument("depth", which + "has " + std::to_string(view.depths.size()) +
                                       " depths for " + std::to_string(view.width) + " x " +
                                       std::to_string(view.height) + " pixels");
  if (view.target.size() != view.depths.size())
    throw InvalidArgument("depth", which + "the mask has " + std::to_string(view.target.size()) +
                                       " pixels, the image " + std::to_string(view.depths.size()));
  if (!(view.fx > 0.0) || !(view.fy > 0.0) || !std::isfinite(view.fx) || !std::isfinite(view.fy) ||
      !std::isfinite(view.cx) || !std::isfinite(view.cy))
    throw InvalidArgument("depth", which + "needs positive focal lengths and a finite centre");
  if (!view.camera.matrix().allFinite())
    throw InvalidArgument("depth", which + "the camera's pose must be finite");
}

/// One view as the carving reads it: every pixel with a depth (a missing
/// one takes the nearest reading within two pixels) and whether it saw the
/// object or, coming down on it, the support.
struct Pixels {
  std::vector<float> depth;
  std::vector<std::uint8_t> target, support;
};

/// The mean of the object's readings within two pixels of (u, v): an
/// object pixel's depth with the sensor's noise averaged out, as the
/// smoothing does for the points (a reading nearer than the surface would
/// otherwise keep space in front of it).
float meanObjectDepth(const DepthEvidence& view, int u, int v) {
  double sum = 0.0;
  int count = 0;
  for (int dv = -2; dv <= 2; ++dv)
    for (int du = -2; du <= 2; ++du) {
      const int uu = u + du, vv = v + dv;
      if (uu < 0 || vv < 0 || uu >= view.width || vv >= view.height) continue;
      const std::size_t j = std::size_t(vv) * std::size_t(view.width) + std::size_t(uu);
      if (!view.target[j] || !hasReading(view.depths[j])) continue;
      sum += static_cast<double>(view.depths[j]);
      ++count;
    }
  return static_cast<float>(sum / count);
}

Pixels readPixels(const DepthEvidence& view) {
  Pixels out;
  out.depth = view.depths;
  out.target = view.target;
  for (int v = 0; v < view.height; ++v)
    for (int u = 0; u < view.width; ++u) {
      const std::size_t i = std::size_t(v) * std::size_t(view.width) + std::size_t(u);
      if (hasReading(view.depths[i])) {
        if (view.target[i]) out.depth[i] = meanObjectDepth(view, u, v);
        continue;
      }
      float nearest = 0.0f;
      std::uint8_t target = 0;
      for (int dv = -2; dv <= 2; ++dv)
        for (int du = -2; du <= 2; ++du) {
          const int uu = u + du, vv = v + dv;
          if (uu < 0 || vv < 0 || uu >= view.width || vv >= view.height) continue;
          const std::size_t j = std::size_t(vv) * std::size_t(view.width) + std::size_t(uu);
          if (!hasReading(view.depths[j])) continue;
          if (nearest == 0.0f || view.depths[j] < nearest) {
            nearest = view.depths[j];
            target = view.target[j];
          }
        }
      out.depth[i] = nearest;
      out.target[i] = nearest > 0.0f && target != 0;
    }
  return out;
}

/// The pixel's point in the world.
Eigen::Vector3d pointAt(const DepthEvidence& view, int u, int v, double depth) {
  return view.camera *
         Eigen::Vector3d((u - view.cx) * depth / view.fx, (v - view.cy) * depth / view.fy, depth);
}

/// The highest horizontal plane among the other pixels' points near the
/// object and not above `lowest` (+ the margin), at the object's centre.
std::optional<double> fitSupport(const std::vector<DepthEvidence>& views,
                                 const std::vector<Pixels>& pixels, const Eigen::Vector3d& low,
                                 const Eigen::Vector3d& high, double reach) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  for (std::size_t k = 0; k < views.size(); ++k)
    for (int v = 0; v < views[k].height; ++v)
      for (int u = 0; u < views[k].width; ++u) {
        const std::size_t i = std::size_t(v) * std::size_t(views[k].width) + std::size_t(u);
        if (pixels[k].target[i] || !hasReading(views[k].depths[i])) continue;
        const Eigen::Vector3d p = pointAt(views[k], u, v, static_cast<double>(views[k].depths[i]));
        if (p.z() > low.z() + kCarvingMargin || p.z() < low.z() - reach) continue;
        if ((p.head<2>().array() < low.head<2>().array() - reach).any() ||
            (p.head<2>().array() > high.head<2>().array() + reach).any())
          continue;
        cloud->push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                       static_cast<float>(p.z())));
      }
  const Eigen::Vector2d centre = 0.5 * (low + high).head<2>();
  // RANSAC's complaints about degenerate samples are no news here.
  const pcl::console::VERBOSITY_LEVEL verbosity = pcl::console::getVerbosityLevel();
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  // Plane after plane, each one's inliers taken out; the support is the
  // highest of those with at least a quarter of the largest one's inliers
  // (a few stray readings also lie on some plane).
  std::vector<std::pair<double, std::size_t>> planes;  // height at the centre, inliers
  for (int round = 0; round < 4 && cloud->size() >= kLeastSupportInliers; ++round) {
    pcl::SampleConsensusModelPerpendicularPlane<pcl::PointXYZ>::Ptr model(
        new pcl::SampleConsensusModelPerpendicularPlane<pcl::PointXYZ>(cloud));
    model->setAxis(Eigen::Vector3f::UnitZ());
    model->setEpsAngle(kSupportTilt);
    pcl::RandomSampleConsensus<pcl::PointXYZ> ransac(model, kCarvingMargin);
    ransac.setMaxIterations(500);
    if (!ransac.computeModel()) break;
    std::vector<int> inliers;
    ransac.getInliers(inliers);
    if (inliers.size() < kLeastSupportInliers) break;
    Eigen::VectorXf coarse, fitted;
    ransac.getModelCoefficients(coarse);
    model->optimizeModelCoefficients(inliers, coarse, fitted);  // least squares
    const Eigen::Vector4d c =
        fitted.size() == 4 ? fitted.head<4>().cast<double>().eval() : Eigen::Vector4d::Zero();
    if (std::abs(c[2]) > 1e-6)
      planes.emplace_back(-(c[0] * centre.x() + c[1] * centre.y() + c[3]) / c[2], inliers.size());
    std::vector<std::uint8_t> taken(cloud->size(), 0);
    for (const int i : inliers) taken[static_cast<std::size_t>(i)] = 1;
    pcl::PointCloud<pcl::PointXYZ>::Ptr rest(new pcl::PointCloud<pcl::PointXYZ>);
    for (std::size_t i = 0; i < cloud->size(); ++i)
      if (!taken[i]) rest->push_back((*cloud)[i]);
    cloud = rest;
  }
  pcl::console::setVerbosityLevel(verbosity);
  std::size_t largest = 0;
  for (const auto& plane : planes) largest = std::max(largest, plane.second);
  std::optional<double> best;
  for (const auto& [height, inliers] : planes)
    if (4 * inliers >= largest && height <= low.z() + kCarvingMargin && (!best || height > *best))
      best = height;
  if (best) best = std::min(*best, low.z());
  return best;
}

/// Object pixels on the outline (beside a pixel that is not the
/// object's), and those of them next to a nearer surface, an unseen pixel
/// or the border.
std::pair<std::size_t, std::size_t> outlineOf(const DepthEvidence& view) {
  std::size_t outline = 0, count = 0;
  for (int v = 0; v < view.height; ++v)
    for (int u = 0; u < view.width; ++u) {
      const std::size_t i = std::size_t(v) * std::size_t(view.width) + std::size_t(u);
      if (!view.target[i] || !hasReading(view.depths[i])) continue;
      bool edge = false, hidden = false;
      for (const auto& [du, dv] : {std::array{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int uu = u + du, vv = v + dv;
        if (uu < 0 || vv < 0 || uu >= view.width || vv >= view.height) {
          edge = hidden = true;
          continue;
        }
        const std::size_t j = std::size_t(vv) * std::size_t(view.width) + std::size_t(uu);
        if (view.target[j]) continue;
        edge = true;
        if (!hasReading(view.depths[j]) ||
            view.depths[j] < view.depths[i] - static_cast<float>(kCarvingMargin))
          hidden = true;
      }
      outline += edge;
      count += hidden;
    }
  return {outline, count};
}

}  // namespace

Carving carveViews(const std::vector<DepthEvidence>& views, const Vertices& points, double reach,
                   std::optional<double> floor) {
  if (views.empty()) throw InvalidArgument("depth", "needs at least one depth image");
  for (std::size_t k = 0; k < views.size(); ++k) checkEvidence(views[k], k);
  checkViewPoints(points);
  if (!(reach > 0.0) || !std::isfinite(reach))
    throw InvalidArgument("reach", "must be a positive distance (m)");
  if (floor && !std::isfinite(*floor)) throw InvalidArgument("floor", "must be finite");
  const Eigen::Vector3d low = points.colwise().minCoeff().transpose();
  const Eigen::Vector3d high = points.colwise().maxCoeff().transpose();

  Carving out;
  out.reach = reach;
  std::vector<Pixels> pixels;
  for (const DepthEvidence& view : views) pixels.push_back(readPixels(view));
  const std::optional<double> fitted =
      floor ? std::nullopt : fitSupport(views, pixels, low, high, reach);
  out.floor = floor ? *floor : fitted.value_or(low.z());
  out.floor_fitted = fitted.has_value();
  if (out.floor > high.z())
    throw InvalidArgument("floor", "lies above every point (" + std::to_string(out.floor) + " > " +
                                       std::to_string(high.z()) + ")");
  for (const DepthEvidence& view : views) {
    const auto [outline, occluded] = outlineOf(view);
    out.outline.push_back(outline);
    out.occluded.push_back(occluded);
  }

  // Which pixels come down on the support: the object, standing on it, is
  // not behind them.
  for (std::size_t k = 0; k < views.size(); ++k) {
    pixels[k].support.assign(pixels[k].depth.size(), 0);
    const Eigen::Vector3d eye = views[k].camera.translation();
    for (int v = 0; v < views[k].height; ++v)
      for (int u = 0; u < views[k].width; ++u) {
        const std::size_t i = std::size_t(v) * std::size_t(views[k].width) + std::size_t(u);
        if (pixels[k].target[i] || pixels[k].depth[i] <= 0.0f) continue;
        const Eigen::Vector3d p = pointAt(views[k], u, v, static_cast<double>(pixels[k].depth[i]));
        pixels[k].support[i] = p.z() <= out.floor + kCarvingMargin && p.z() < eye.z();
      }
  }

  // The block: the points' box grown by the reach, from the floor up.
  // Its voxels on the grid of the points' frame (multiples of the edge),
  // so that a cloud of the same edge holds them exactly
  // (robot::withHiddenSide); the lowest layer may reach below the floor.
  const Eigen::Vector3d first(low.x() - reach, low.y() - reach, out.floor);
  const Eigen::Vector3d last(high.x() + reach, high.y() + reach, high.z() + reach);
  out.voxel = std::max(kFinestVoxel, std::cbrt((last - first).prod() / kMostVoxels));
  const Eigen::Vector3d start = (first / out.voxel).array().floor().matrix() * out.voxel;
  const Eigen::Vector3d extent = last - start;
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a)
    dims[a] = std::max(1, static_cast<int>(std::ceil(extent[a] / out.voxel)));
  const auto index = [&dims](int i, int j, int k) {
    return std::size_t(i) +
           std::size_t(dims[0]) * (std::size_t(j) + std::size_t(dims[1]) * std::size_t(k));
  };
  const auto centreOf = [&](int i, int j, int k) {
    return Eigen::Vector3d(start + out.voxel * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5));
  };

  const std::size_t cells = static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]) *
                            static_cast<std::size_t>(dims[2]);
  std::vector<std::uint8_t> possible(cells, 1);
  for (std::size_t k = 0; k < views.size(); ++k) {
    const DepthEvidence& view = views[k];
    const Eigen::Isometry3d toCamera = view.camera.inverse();
    for (int z = 0; z < dims[2]; ++z)
      for (int y = 0; y < dims[1]; ++y)
        for (int x = 0; x < dims[0]; ++x) {
          const std::size_t cell = index(x, y, z);
          if (!possible[cell]) continue;
          const Eigen::Vector3d c = toCamera * centreOf(x, y, z);
          if (c.z() <= 0.0) continue;
          const long u = std::lround(view.fx * c.x() / c.z() + view.cx);
          const long v = std::lround(view.fy * c.y() / c.z() + view.cy);
          if (u < 0 || v < 0 || u >= view.width || v >= view.height) continue;
          const std::size_t i = std::size_t(v) * std::size_t(view.width) + std::size_t(u);
          const double depth = static_cast<double>(pixels[k].depth[i]);
          if (depth <= 0.0) continue;
          const bool free = pixels[k].target[i]    ? c.z() < depth
                            : pixels[k].support[i] ? true
                                                   : c.z() < depth - kCarvingMargin;
          if (free) possible[cell] = 0;
        }
  }

  // What connects to the observed points.
  std::vector<std::uint8_t> reached(possible.size(), 0);
  std::deque<std::array<int, 3>> queue;
  const auto visit = [&](int x, int y, int z) {
    if (x < 0 || y < 0 || z < 0 || x >= dims[0] || y >= dims[1] || z >= dims[2]) return;
    const std::size_t cell = index(x, y, z);
    if (!possible[cell] || reached[cell]) return;
    reached[cell] = 1;
    queue.push_back({x, y, z});
  };
  for (Eigen::Index p = 0; p < points.rows(); ++p) {
    const Eigen::Vector3d g = (points.row(p).transpose() - start) / out.voxel;
    const int x = static_cast<int>(std::floor(g.x())), y = static_cast<int>(std::floor(g.y())),
              z = static_cast<int>(std::floor(g.z()));
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) visit(x + dx, y + dy, z + dz);
  }
  std::vector<Eigen::Vector3d> centres;
  while (!queue.empty()) {
    const auto [x, y, z] = queue.front();
    queue.pop_front();
    centres.push_back(centreOf(x, y, z));
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) visit(x + dx, y + dy, z + dz);
  }
  out.centres.resize(static_cast<Eigen::Index>(centres.size()), 3);
  for (std::size_t i = 0; i < centres.size(); ++i)
    out.centres.row(static_cast<Eigen::Index>(i)) = centres[i].transpose();
  return out;
}

std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> mergedVoxels(const Vertices& centres,
                                                                      double voxel) {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> boxes;
  if (centres.rows() == 0) return boxes;
  if (!(voxel > 0.0) || !std::isfinite(voxel))
    throw InvalidArgument("voxel", "must be a positive number");
  const Eigen::Vector3d origin = centres.colwise().minCoeff().transpose();
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a)
    dims[a] = static_cast<int>(std::lround((centres.col(a).maxCoeff() - origin[a]) / voxel)) + 1;
  const auto index = [&dims](int x, int y, int z) {
    return static_cast<std::size_t>(x) +
           static_cast<std::size_t>(dims[0]) *
               (static_cast<std::size_t>(y) +
                static_cast<std::size_t>(dims[1]) * static_cast<std::size_t>(z));
  };
  std::vector<std::uint8_t> open(static_cast<std::size_t>(dims[0]) *
                                     static_cast<std::size_t>(dims[1]) *
                                     static_cast<std::size_t>(dims[2]),
                                 0);
  for (Eigen::Index i = 0; i < centres.rows(); ++i) {
    const Eigen::Vector3d g = (centres.row(i).transpose() - origin) / voxel;
    open[index(static_cast<int>(std::lround(g.x())), static_cast<int>(std::lround(g.y())),
               static_cast<int>(std::lround(g.z())))] = 1;
  }
  for (int z = 0; z < dims[2]; ++z)
    for (int y = 0; y < dims[1]; ++y)
      for (int x = 0; x < dims[0]; ++x) {
        if (!open[index(x, y, z)]) continue;
        int x1 = x + 1, y1 = y + 1, z1 = z + 1;  // one past the box's last cube
        while (x1 < dims[0] && open[index(x1, y, z)]) ++x1;
        const auto rowOpen = [&](int yy, int zz) {
          for (int xx = x; xx < x1; ++xx)
            if (!open[index(xx, yy, zz)]) return false;
          return true;
        };
        while (y1 < dims[1] && rowOpen(y1, z)) ++y1;
        const auto layerOpen = [&](int zz) {
          for (int yy = y; yy < y1; ++yy)
            if (!rowOpen(yy, zz)) return false;
          return true;
        };
        while (z1 < dims[2] && layerOpen(z1)) ++z1;
        for (int zz = z; zz < z1; ++zz)
          for (int yy = y; yy < y1; ++yy)
            for (int xx = x; xx < x1; ++xx) open[index(xx, yy, zz)] = 0;
        const Eigen::Vector3d low =
            origin + voxel * (Eigen::Vector3d(x, y, z).array() - 0.5).matrix();
        const Eigen::Vector3d high =
            origin + voxel * (Eigen::Vector3d(x1, y1, z1).array() - 0.5).matrix();
        boxes.emplace_back(low, high);
      }
  return boxes;
}

}  // namespace hfts::preprocess
