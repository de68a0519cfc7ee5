#pragma once
// Distance grids of triangle meshes: how far each node of a regular grid is
// from the mesh's surface, stored so that it never overestimates. The
// conservative (sphere) tier of collision checking uses them to tell a
// sphere near the target object or a mesh obstacle from one touching it.

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "hfts_db/triangle_mesh.h"

namespace hfts::db {

/// Distances from a triangle mesh's surface sampled on a regular grid
/// (mesh/object frame, metres).
///
/// d(x) below is the distance from x to the nearest point of any triangle;
/// for a signed grid, sd(x) is -d(x) inside the solid (winding number of
/// the closed mesh not 0) and d(x) elsewhere; for an unsigned grid sd = d.
/// sd is 1-Lipschitz. Invariants of a non-empty grid (buildDistanceGrid
/// makes them hold, the object database checks the structural ones):
/// - values[index(i, j, k)] <= sd(node(i, j, k)): the exact distance in
///   double, rounded down to float;
/// - the whole surface lies in the box of the nodes, [origin, boxMax()].
struct DistanceGrid {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< position of node (0,0,0)
  double spacing = 0.0;                              ///< node spacing (m), > 0 unless empty
  std::array<std::uint32_t, 3> dims{0, 0, 0};        ///< nodes along x, y, z
  bool is_signed = false;     ///< negative inside (closed meshes); else unsigned distances
  std::vector<float> values;  ///< index x + dims[0] * (y + dims[1] * z)
  /// Not above the smallest value on the six faces of the box (derived
  /// from `values`, not stored in files: buildDistanceGrid and
  /// loadObjectDatabase set it to boundaryMinimum()). Only lowerBound
  /// outside the box uses it; the default proves nothing there beyond the
  /// box's own distance, and is always valid.
  float boundary_min = -std::numeric_limits<float>::infinity();

  bool empty() const { return values.empty(); }
  std::size_t index(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
    return x + std::size_t{dims[0]} * (y + std::size_t{dims[1]} * z);
  }
  /// Coordinate of the nodes with index i along `axis` (0 = x, 1 = y, 2 = z).
  double coordinate(int axis, std::uint32_t i) const {
    return origin[axis] + spacing * static_cast<double>(i);
  }
  /// Position of node (x, y, z): origin + spacing * (x, y, z), per coordinate().
  Eigen::Vector3d node(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
    return {coordinate(0, x), coordinate(1, y), coordinate(2, z)};
  }
  /// The last node, the corner of the grid's box opposite to `origin`.
  Eigen::Vector3d boxMax() const;

  /// A lower bound of sd(p), valid for every finite point p:
  /// - inside the box: L(p) = values[g] - |p - g| with g the node nearest
  ///   to p (sd is 1-Lipschitz). It is at least sd(p) - 2 |p - g|, so
  ///   within sqrt(3) * spacing (plus float rounding) of sd(p).
  /// - outside the box: sqrt(D^2 + (L' - M)^2) + M, with q the point of the
  ///   box nearest to p, D = |p - q|, M = max(0, boundary_min -
  ///   spacing / sqrt(2)) a bound of d on the box's faces and L' =
  ///   max(L(q), M). Why: p is outside the solid, and the segment from p to
  ///   its nearest surface point s leaves the box at some b; the box is
  ///   convex, so |p - b|^2 >= D^2 + |b - q|^2, and d(b) >= max(M, L(q) -
  ///   |b - q|); minimise |p - b| + d(b) over |b - q|. Head-on beyond a face
  ///   this is D + L(q); it never falls below D.
  /// So for a ball of radius r around p, lowerBound(p) > r proves that the
  /// ball does not touch the surface (and, for a signed grid, lies outside
  /// the solid). An empty grid, or a non-finite p, proves nothing: -infinity.
  double lowerBound(const Eigen::Vector3d& p) const;
};

/// The smallest value on the six faces of the grid's box (O(faces)), what
/// DistanceGrid::boundary_min caches; -infinity unless dims are all >= 2
/// and match the values.
float boundaryMinimum(const DistanceGrid& grid);

/// How buildDistanceGrid lays out its grid.
struct DistanceGridOptions {
  /// Node spacing (m); 0 = automatic: the longest side of the mesh's
  /// bounding box / 64, at least 1 mm, and coarser where that would give
  /// more than kAutomaticGridNodes nodes (1 MiB of values).
  double spacing = 0.0;
  /// The grid covers the bounding box plus at least this much (m) on every side.
  double margin = 0.03;
};

/// Node budget of the automatic spacing.
inline constexpr std::uint64_t kAutomaticGridNodes = std::uint64_t{1} << 18;
/// No grid has more nodes (64 MiB of values); a finer explicit spacing is an error.
inline constexpr std::uint64_t kMaxGridNodes = std::uint64_t{1} << 24;

/// The distance grid of `mesh`: exact closest-point distances (Embree's BVH
/// culls, the double-precision point-triangle distance decides) rounded
/// down to float; signed when `closed` (the mesh bounds a solid: inside is
/// where the winding number is not 0, found by counting crossings along
/// grid lines parallel to each axis, majority of the three), unsigned
/// otherwise. The grid is centred on the mesh's bounding box. One thread;
/// 0.3 to 4 us per node (docs/preprocess.md).
/// Throws hfts::InvalidArgument ("DistanceGridOptions::spacing",
/// "DistanceGridOptions::margin") for a negative or non-finite option or
/// more than kMaxGridNodes nodes, and ("mesh") for a mesh without triangles
/// or with non-finite vertices.
DistanceGrid buildDistanceGrid(const TriangleMesh& mesh, bool closed,
                               const DistanceGridOptions& options = {});

}  // namespace hfts::db
