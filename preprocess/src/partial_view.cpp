#include "preprocess/partial_view.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_set>

#include "core/invalid_argument.h"

namespace hfts::preprocess {

void checkViewPoints(const Vertices& points) {
  if (points.rows() < 4)
    throw InvalidArgument("points",
                          "needs at least 4 points, got " + std::to_string(points.rows()));
  if (!points.allFinite()) throw InvalidArgument("points", "must be finite");
}

HiddenSide hiddenSide(const Vertices& points, const ViewOptions& options) {
  checkViewPoints(points);
  if (!options.viewpoint.allFinite()) throw InvalidArgument("viewpoint", "must be finite");
  if (!(options.hidden_depth >= 0.0) || !std::isfinite(options.hidden_depth))
    throw InvalidArgument("hidden_depth", "must be a finite number >= 0 (0: automatic)");
  const Eigen::Vector3d low = points.colwise().minCoeff().transpose();
  const Eigen::Vector3d high = points.colwise().maxCoeff().transpose();
  HiddenSide out;
  out.floor = options.floor.value_or(low.z());
  if (!std::isfinite(out.floor)) throw InvalidArgument("floor", "must be finite");
  if (out.floor > high.z())
    throw InvalidArgument("floor", "lies above every point (" + std::to_string(out.floor) + " > " +
                                       std::to_string(high.z()) + ")");
  out.hidden_depth = options.hidden_depth > 0.0 ? options.hidden_depth : (high - low).maxCoeff();
  out.corners.resize(2 * points.rows(), 3);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const Eigen::Vector3d p = points.row(i).transpose();
    const Eigen::Vector3d ray = p - options.viewpoint;
    if (ray.norm() < 1e-9)
      throw InvalidArgument("viewpoint", "lies on point " + std::to_string(i) + " of the view");
    const Eigen::Vector3d d = ray.normalized();
    // The shadow stops at the floor (a point below it casts none).
    double length = out.hidden_depth;
    if (p.z() <= out.floor)
      length = 0.0;
    else if (d.z() < 0.0)
      length = std::min(length, (p.z() - out.floor) / -d.z());
    out.corners.row(2 * i) = p.transpose();
    out.corners.row(2 * i + 1) = (p + length * d).transpose();
  }
  return out;
}

namespace {

/// What of `a` lies in `b`: a's corners inside b and where a's edges
/// cross b's planes, inside b.
void appendCornersIn(const ConvexHull& a, const ConvexHull& b, std::vector<Eigen::Vector3d>& out) {
  constexpr double kTolerance = 1e-9;
  const db::Points3& v = a.vertices();
  for (Eigen::Index i = 0; i < v.rows(); ++i)
    if (b.depth(v.row(i).transpose()) >= -kTolerance) out.push_back(v.row(i).transpose());
  const db::Faces3& f = a.faces();
  for (Eigen::Index t = 0; t < f.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = v.row(f(t, k)).transpose();
      const Eigen::Vector3d q = v.row(f(t, (k + 1) % 3)).transpose();
      for (Eigen::Index row = 0; row < b.planes().rows(); ++row) {
        const Eigen::Vector4d plane = b.planes().row(row).transpose();
        if (!std::isfinite(plane[3])) continue;  // a sliver's
        const double sp = plane.head<3>().dot(p) + plane[3];
        const double sq = plane.head<3>().dot(q) + plane[3];
        if ((sp < 0.0) == (sq < 0.0) || sp == sq) continue;
        const Eigen::Vector3d x = p + (sp / (sp - sq)) * (q - p);
        if (b.depth(x) >= -kTolerance) out.push_back(x);
      }
    }
}

}  // namespace

Vertices intersectionCorners(const ConvexHull& a, const ConvexHull& b) {
  std::vector<Eigen::Vector3d> corners;
  appendCornersIn(a, b, corners);
  appendCornersIn(b, a, corners);
  // To the micrometre: a corner found twice (where edges of both solids
  // meet) is one point, not two a rounding error apart, whose hull would
  // hold slivers no convexity check passes.
  Vertices out(static_cast<Eigen::Index>(corners.size()), 3);
  for (std::size_t i = 0; i < corners.size(); ++i)
    out.row(static_cast<Eigen::Index>(i)) =
        (corners[i] * 1e6).array().round().matrix().transpose() / 1e6;
  return out;
}

std::vector<std::uint32_t> onePerVoxel(const Vertices& points, double voxel) {
  if (!(voxel > 0.0) || !std::isfinite(voxel))
    throw InvalidArgument("voxel", "must be a positive number");
  // 21 bits per axis: +-1e6 voxels, beyond any object's extent.
  const auto key = [voxel](const Eigen::Vector3d& p) {
    std::uint64_t k = 0;
    for (int a = 0; a < 3; ++a) {
      const auto cell = static_cast<std::int64_t>(std::floor(p[a] / voxel)) + (1 << 20);
      k = (k << 21) |
          (static_cast<std::uint64_t>(std::clamp<std::int64_t>(cell, 0, (1 << 21) - 1)));
    }
    return k;
  };
  std::unordered_set<std::uint64_t> seen;
  std::vector<std::uint32_t> kept;
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    if (seen.insert(key(points.row(i).transpose())).second)
      kept.push_back(static_cast<std::uint32_t>(i));
  return kept;
}

}  // namespace hfts::preprocess
