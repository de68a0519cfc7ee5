#pragma once
// Where a closed mesh's solid lies along lines parallel to one axis: the
// stretches of each line on which the winding number is not 0. The distance
// grid's inside test (which nodes are inside) and the offline stage's convex
// decomposition (which parts of a box are solid, and how much) both count
// crossings this one way.

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "hfts_db/triangle_mesh.h"

namespace hfts::db {

/// Lines parallel to `axis` through the nodes of a regular lattice in the
/// plane of the two other axes, u = (axis + 1) % 3 and v = (axis + 2) % 3:
/// line (i, j) runs through origin[u] + spacing * i, origin[v] + spacing * j.
struct LineLattice {
  int axis = 2;  ///< direction of the lines: 0 = x, 1 = y, 2 = z
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< line (0, 0); origin[axis] is not used
  double spacing = 0.0;                              ///< between neighbouring lines (m), > 0
  std::array<std::uint32_t, 2> counts{0, 0};         ///< lines along u and along v

  int u() const { return (axis + 1) % 3; }
  int v() const { return (axis + 2) % 3; }
  std::size_t lines() const { return std::size_t{counts[0]} * counts[1]; }
  std::size_t index(std::uint32_t i, std::uint32_t j) const {
    return i + std::size_t{counts[0]} * j;
  }
  /// Coordinate along u (k = 0) or v (k = 1) of the lines with index i there.
  double coordinate(int k, std::uint32_t i) const {
    return origin[k == 0 ? u() : v()] + spacing * static_cast<double>(i);
  }
};

/// One stretch of a line inside the solid: the points whose coordinate c
/// along the line has enter < c <= exit.
struct Interval {
  double enter = 0.0;
  double exit = 0.0;
};

/// The solid along every line of a lattice: line l's intervals are
/// intervals[first[l]] .. intervals[first[l + 1] - 1], sorted and disjoint.
struct WindingLines {
  LineLattice lattice;
  std::vector<std::uint32_t> first;  ///< lattice.lines() + 1 offsets
  std::vector<Interval> intervals;
  /// Per line, the integral of max(|w| - 1, 0) along it: how much more than
  /// once closed parts that overlap cover it (0 where none do). The
  /// divergence theorem counts that much twice or more; the solid, once.
  std::vector<double> overlap;

  const Interval* begin(std::size_t line) const { return intervals.data() + first[line]; }
  const Interval* end(std::size_t line) const { return intervals.data() + first[line + 1]; }
  /// Whether coordinate c of line `line` lies in the solid.
  bool inside(std::size_t line, double c) const;
  /// Length of the solid on line `line` between the coordinates lo and hi.
  double length(std::size_t line, double lo, double hi) const;
};

/// Where the solid of `mesh` lies along the lines of `lattice`: the winding
/// number at a point of a line is the sum of the signs (+1 where the mesh's
/// outward side faces up the line) of the triangles the line crosses below
/// it, and the solid is where it is not 0. A line through an edge or vertex
/// counts as if moved infinitesimally in one fixed direction (simulation of
/// simplicity), so it crosses a closed surface consistently; triangles
/// parallel to the lines are never crossed. Closed parts that overlap (w =
/// 2 inside both) and inward winding (w = -1) are handled. Meant for closed
/// meshes: an open one gives intervals that do not mean inside.
/// Throws hfts::InvalidArgument ("lattice.axis", "lattice.spacing",
/// "lattice.origin") for a bad lattice and ("mesh") for a mesh with
/// non-finite vertices or an index out of range.
WindingLines windingLines(const TriangleMesh& mesh, const LineLattice& lattice);

}  // namespace hfts::db
