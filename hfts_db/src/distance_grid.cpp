// Distance grids: the conservative lower bound, the layout and the builder.
#include "hfts_db/distance_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/invalid_argument.h"
#include "grid_winding.h"
#include "hfts_db/triangle_bvh.h"

namespace hfts::db {
namespace {

constexpr double kAutomaticDivisions = 64.0;  ///< of the longest bounding-box side
constexpr double kMinAutomaticSpacing = 0.001;

/// The float nearest below (or at) `value`: a lower bound stays one.
float roundedDown(double value) {
  float f = static_cast<float>(value);
  if (static_cast<double>(f) > value)
    f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

struct Box {
  Eigen::Vector3d lo, hi;
};

void checkMesh(const TriangleMesh& mesh) {
  if (mesh.triangles.rows() == 0) throw InvalidArgument("mesh", "has no triangles");
  if (!mesh.vertices.allFinite()) throw InvalidArgument("mesh", "has non-finite vertices");
  if (static_cast<Eigen::Index>(mesh.triangles.maxCoeff()) >= mesh.vertices.rows())
    throw InvalidArgument("mesh", "a triangle indexes a vertex that does not exist");
}

void checkOptions(const DistanceGridOptions& options) {
  if (!(options.spacing >= 0.0) || !std::isfinite(options.spacing))
    throw InvalidArgument("DistanceGridOptions::spacing",
                          "must be >= 0 (0 = automatic), got " + std::to_string(options.spacing));
  if (!(options.margin >= 0.0) || !std::isfinite(options.margin))
    throw InvalidArgument("DistanceGridOptions::margin",
                          "must be >= 0, got " + std::to_string(options.margin));
}

/// Nodes along one axis covering `span` at `spacing` (at least 2), as a
/// double so that absurd requests do not overflow before they are refused.
double nodesAlong(double span, double spacing) {
  return std::max(2.0, std::ceil(span / spacing) + 1.0);
}

double nodeCount(const Eigen::Vector3d& span, double spacing) {
  return nodesAlong(span.x(), spacing) * nodesAlong(span.y(), spacing) *
         nodesAlong(span.z(), spacing);
}

double automaticSpacing(const Box& box, const Eigen::Vector3d& span) {
  double spacing =
      std::max((box.hi - box.lo).maxCoeff() / kAutomaticDivisions, kMinAutomaticSpacing);
  const auto budget = static_cast<double>(kAutomaticGridNodes);
  for (double n = nodeCount(span, spacing); n > budget; n = nodeCount(span, spacing))
    spacing *= std::max(std::cbrt(n / budget), 1.001);
  return spacing;
}

/// The grid's nodes, centred on the box, covering it plus `margin` on every
/// side; values not yet filled.
DistanceGrid layOut(const Box& box, const DistanceGridOptions& options) {
  const Eigen::Vector3d span = (box.hi - box.lo).array() + 2.0 * options.margin;
  DistanceGrid grid;
  grid.spacing = options.spacing > 0.0 ? options.spacing : automaticSpacing(box, span);
  const double n = nodeCount(span, grid.spacing);
  if (n > static_cast<double>(kMaxGridNodes))
    throw InvalidArgument("DistanceGridOptions::spacing",
                          std::to_string(grid.spacing) + " m with a margin of " +
                              std::to_string(options.margin) + " m gives " + std::to_string(n) +
                              " nodes, more than " + std::to_string(kMaxGridNodes) +
                              "; choose a coarser spacing");
  for (int c = 0; c < 3; ++c) {
    const double centre = 0.5 * (box.lo[c] + box.hi[c]);
    auto nodes = static_cast<std::uint32_t>(nodesAlong(span[c], grid.spacing));
    for (;; ++nodes) {  // one more node where rounding leaves the box uncovered
      grid.dims[static_cast<std::size_t>(c)] = nodes;
      grid.origin[c] = centre - 0.5 * grid.spacing * (nodes - 1.0);
      if (grid.origin[c] <= box.lo[c] - options.margin &&
          grid.coordinate(c, nodes - 1) >= box.hi[c] + options.margin)
        break;
    }
  }
  return grid;
}

void fillDistances(DistanceGrid& grid, const TriangleMesh& mesh,
                   const std::vector<std::uint8_t>& inside) {
  const TriangleBvh bvh(mesh);
  grid.values.resize(std::size_t{grid.dims[0]} * grid.dims[1] * grid.dims[2]);
  std::uint32_t hint = 0;  // the last nearest triangle: neighbours share it
  for (std::uint32_t z = 0; z < grid.dims[2]; ++z)
    for (std::uint32_t y = 0; y < grid.dims[1]; ++y)
      for (std::uint32_t x = 0; x < grid.dims[0]; ++x) {
        const ClosestPoint nearest = bvh.closestPoint(grid.node(x, y, z), hint);
        hint = nearest.triangle;
        const std::size_t i = grid.index(x, y, z);
        const bool in = !inside.empty() && inside[i] != 0;
        grid.values[i] = roundedDown(in ? -nearest.distance : nearest.distance);
      }
}

}  // namespace

Eigen::Vector3d DistanceGrid::boxMax() const {
  return node(dims[0] - 1, dims[1] - 1, dims[2] - 1);
}

double DistanceGrid::lowerBound(const Eigen::Vector3d& p) const {
  if (empty() || !p.allFinite()) return -std::numeric_limits<double>::infinity();
  Eigen::Vector3d q;  // the point of the box nearest to p
  std::array<std::uint32_t, 3> g;
  for (int c = 0; c < 3; ++c) {
    const std::size_t k = static_cast<std::size_t>(c);
    q[c] = std::clamp(p[c], origin[c], coordinate(c, dims[k] - 1));
    const double t = std::round((q[c] - origin[c]) / spacing);
    g[k] = static_cast<std::uint32_t>(std::clamp(t, 0.0, dims[k] - 1.0));
  }
  const double atQ =
      static_cast<double>(values[index(g[0], g[1], g[2])]) - (q - node(g[0], g[1], g[2])).norm();
  const double outside = (p - q).squaredNorm();
  if (outside == 0.0) return atQ;
  // On a face every point is within spacing / sqrt(2) of a face node.
  const double onFaces =
      std::max(0.0, static_cast<double>(boundary_min) - spacing * std::sqrt(0.5));
  const double beyond = std::max(atQ, onFaces) - onFaces;
  return std::sqrt(outside + beyond * beyond) + onFaces;
}

float boundaryMinimum(const DistanceGrid& grid) {
  const std::uint32_t nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  if (nx < 2 || ny < 2 || nz < 2 || grid.values.size() != std::size_t{nx} * ny * nz)
    return -std::numeric_limits<float>::infinity();  // not a valid grid: nothing is known
  float smallest = std::numeric_limits<float>::infinity();
  for (std::uint32_t z = 0; z < nz; ++z)
    for (std::uint32_t y = 0; y < ny; ++y) {
      const bool face = z == 0 || z == nz - 1 || y == 0 || y == ny - 1;
      // Whole rows on the z and y faces, only the two ends of the others.
      for (std::uint32_t x = 0; x < nx; x += face || x + 1 == nx ? 1 : nx - 1)
        smallest = std::min(smallest, grid.values[grid.index(x, y, z)]);
    }
  return smallest;
}

DistanceGrid buildDistanceGrid(const TriangleMesh& mesh, bool closed,
                               const DistanceGridOptions& options) {
  checkOptions(options);
  checkMesh(mesh);
  const Box box{mesh.vertices.colwise().minCoeff().transpose(),
                mesh.vertices.colwise().maxCoeff().transpose()};
  DistanceGrid grid = layOut(box, options);
  grid.is_signed = closed;
  fillDistances(grid, mesh, closed ? insideNodes(mesh, grid) : std::vector<std::uint8_t>{});
  grid.boundary_min = boundaryMinimum(grid);
  return grid;
}

}  // namespace hfts::db
