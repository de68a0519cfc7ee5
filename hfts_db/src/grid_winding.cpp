// Inside/outside of grid nodes by counting signed crossings along grid
// lines. Each triangle is "rasterised" onto the lattice of lines parallel
// to one axis. A line through an edge or vertex of the projected mesh is
// counted as if moved infinitesimally in one fixed direction (simulation of
// simplicity), so it crosses a closed surface consistently: the two
// triangles of an edge evaluate the edge in the same canonical order and
// see exactly opposite values.
#include "grid_winding.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace hfts::db {
namespace {

using Point2 = std::array<double, 2>;

bool lexLess(const Point2& a, const Point2& b) {
  return a[0] < b[0] || (a[0] == b[0] && a[1] < b[1]);
}

/// Twice the signed area of (a, b, q), evaluated from the lexicographically
/// smaller end of the edge so that both triangles of an edge get the same
/// number (negated). It is exactly 0 at either end of the edge.
double edgeFunction(const Point2& a, const Point2& b, const Point2& q) {
  const bool canonical = lexLess(a, b);
  const Point2& p0 = canonical ? a : b;
  const Point2& p1 = canonical ? b : a;
  const double e = (p1[0] - p0[0]) * (q[1] - p0[1]) - (p1[1] - p0[1]) * (q[0] - p0[0]);
  return canonical ? e : -e;
}

/// Where one triangle crosses one grid line.
struct Crossing {
  std::size_t line;  ///< i + dims[u] * j
  double depth;      ///< coordinate along the axis
  int sign;          ///< orientation of the projected triangle
  bool operator<(const Crossing& o) const {
    return line < o.line || (line == o.line && depth < o.depth);
  }
};

/// The lattice lines along `axis` a triangle's projection may cover: the
/// index range of its bounding interval, widened by one for rounding.
std::array<std::uint32_t, 2> lineRange(const DistanceGrid& grid, int axis, double lo, double hi) {
  const double last = grid.dims[axis] - 1.0;
  const double first = std::floor((lo - grid.origin[axis]) / grid.spacing) - 1.0;
  const double end = std::ceil((hi - grid.origin[axis]) / grid.spacing) + 1.0;
  return {static_cast<std::uint32_t>(std::clamp(first, 0.0, last)),
          static_cast<std::uint32_t>(std::clamp(end, 0.0, last))};
}

class LineCrossings {
 public:
  LineCrossings(const DistanceGrid& grid, int axis)
      : grid_(grid), a_(axis), u_((axis + 1) % 3), v_((axis + 2) % 3) {}

  /// Records the lines triangle (A, B, C) crosses.
  void add(const Eigen::Vector3d& A, const Eigen::Vector3d& B, const Eigen::Vector3d& C) {
    const std::array<Point2, 3> p = {project(A), project(B), project(C)};
    const double area = edgeFunction(p[0], p[1], p[2]);
    if (area == 0.0) return;  // parallel to the lines: no crossing
    const auto [i0, i1] = lineRange(grid_, u_, std::min({p[0][0], p[1][0], p[2][0]}),
                                    std::max({p[0][0], p[1][0], p[2][0]}));
    const auto [j0, j1] = lineRange(grid_, v_, std::min({p[0][1], p[1][1], p[2][1]}),
                                    std::max({p[0][1], p[1][1], p[2][1]}));
    for (std::uint32_t j = j0; j <= j1; ++j)
      for (std::uint32_t i = i0; i <= i1; ++i) {
        const Point2 q = {grid_.coordinate(u_, i), grid_.coordinate(v_, j)};
        std::array<double, 3> w;  // w[k]: edge opposite corner k
        bool covered = true;
        for (int k = 0; k < 3 && covered; ++k) {
          const Point2& from = p[(k + 1) % 3];
          const Point2& to = p[(k + 2) % 3];
          w[k] = edgeFunction(from, to, q);
          covered = ownsPoint(w[k], area, from, to);
        }
        const double sum = w[0] + w[1] + w[2];  // the area again, up to rounding
        if (!covered || sum == 0.0) continue;
        const double depth = (w[0] * A[a_] + w[1] * B[a_] + w[2] * C[a_]) / sum;
        crossings_.push_back({i + std::size_t{grid_.dims[u_]} * j, depth, area > 0.0 ? 1 : -1});
      }
  }

  /// Adds 1 to votes[node] for every node whose winding number along its
  /// line is not 0.
  void vote(std::vector<std::uint8_t>& votes) {
    std::sort(crossings_.begin(), crossings_.end());
    for (std::size_t c = 0; c < crossings_.size();) {
      const std::size_t line = crossings_[c].line;
      const auto i = static_cast<std::uint32_t>(line % grid_.dims[u_]);
      const auto j = static_cast<std::uint32_t>(line / grid_.dims[u_]);
      int winding = 0;
      for (std::uint32_t k = 0; k < grid_.dims[a_]; ++k) {
        const double at = grid_.coordinate(a_, k);
        for (; c < crossings_.size() && crossings_[c].line == line && crossings_[c].depth < at; ++c)
          winding += crossings_[c].sign;
        if (winding == 0) continue;
        std::array<std::uint32_t, 3> n;
        n[static_cast<std::size_t>(a_)] = k;
        n[static_cast<std::size_t>(u_)] = i;
        n[static_cast<std::size_t>(v_)] = j;
        ++votes[grid_.index(n[0], n[1], n[2])];
      }
      while (c < crossings_.size() && crossings_[c].line == line) ++c;
    }
  }

 private:
  Point2 project(const Eigen::Vector3d& x) const { return {x[u_], x[v_]}; }

  /// Whether the point where the edge (from, to) has value `w` belongs to
  /// the triangle: strictly on its inner side, or on the edge with the
  /// triangle on the side of the fixed perturbation (-eps, 1), which lies
  /// to the left of the edge's lexicographic direction.
  static bool ownsPoint(double w, double area, const Point2& from, const Point2& to) {
    if (w != 0.0) return (w > 0.0) == (area > 0.0);
    return (area > 0.0) == lexLess(from, to);
  }

  const DistanceGrid& grid_;
  int a_, u_, v_;
  std::vector<Crossing> crossings_;
};

}  // namespace

std::vector<std::uint8_t> insideNodes(const TriangleMesh& mesh, const DistanceGrid& grid) {
  std::vector<std::uint8_t> votes(
      std::size_t{grid.dims[0]} * std::size_t{grid.dims[1]} * std::size_t{grid.dims[2]}, 0);
  for (int axis = 0; axis < 3; ++axis) {
    LineCrossings lines(grid, axis);
    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
      lines.add(mesh.vertices.row(mesh.triangles(t, 0)), mesh.vertices.row(mesh.triangles(t, 1)),
                mesh.vertices.row(mesh.triangles(t, 2)));
    lines.vote(votes);
  }
  for (std::uint8_t& v : votes) v = v >= 2 ? 1 : 0;
  return votes;
}

}  // namespace hfts::db
