// Signed crossings of a mesh along the lines of a lattice. Each triangle is
// "rasterised" onto the lattice. A line through an edge or vertex of the
// projected mesh is counted as if moved infinitesimally in one fixed
// direction (simulation of simplicity), so it crosses a closed surface
// consistently: the two triangles of an edge evaluate the edge in the same
// canonical order and see exactly opposite values.
#include "hfts_db/winding_lines.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/invalid_argument.h"

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

/// Whether the point where the edge (from, to) has value `w` belongs to the
/// triangle: strictly on its inner side, or on the edge with the triangle
/// on the side of the fixed perturbation (-eps, 1), which lies to the left
/// of the edge's lexicographic direction.
bool ownsPoint(double w, double area, const Point2& from, const Point2& to) {
  if (w != 0.0) return (w > 0.0) == (area > 0.0);
  return (area > 0.0) == lexLess(from, to);
}

/// Where one triangle crosses one line.
struct Crossing {
  std::size_t line;
  double depth;  ///< coordinate along the line
  int sign;      ///< orientation of the projected triangle
  bool operator<(const Crossing& o) const {
    return line < o.line || (line == o.line && depth < o.depth);
  }
};

/// The lines (along lattice direction k) a triangle's projection may cover:
/// the index range of its bounding interval, widened by one for rounding.
std::array<std::uint32_t, 2> lineRange(const LineLattice& lattice, int k, double lo, double hi) {
  const double last = lattice.counts[static_cast<std::size_t>(k)] - 1.0;
  const double origin = lattice.coordinate(k, 0);
  const double first = std::floor((lo - origin) / lattice.spacing) - 1.0;
  const double end = std::ceil((hi - origin) / lattice.spacing) + 1.0;
  return {static_cast<std::uint32_t>(std::clamp(first, 0.0, last)),
          static_cast<std::uint32_t>(std::clamp(end, 0.0, last))};
}

/// Appends the crossings of triangle (A, B, C) with the lattice's lines.
void addCrossings(const LineLattice& lattice, const Eigen::Vector3d& A, const Eigen::Vector3d& B,
                  const Eigen::Vector3d& C, std::vector<Crossing>& out) {
  const int a = lattice.axis, u = lattice.u(), v = lattice.v();
  const std::array<Point2, 3> p = {Point2{A[u], A[v]}, Point2{B[u], B[v]}, Point2{C[u], C[v]}};
  const double area = edgeFunction(p[0], p[1], p[2]);
  if (area == 0.0) return;  // parallel to the lines: no crossing
  const auto [i0, i1] = lineRange(lattice, 0, std::min({p[0][0], p[1][0], p[2][0]}),
                                  std::max({p[0][0], p[1][0], p[2][0]}));
  const auto [j0, j1] = lineRange(lattice, 1, std::min({p[0][1], p[1][1], p[2][1]}),
                                  std::max({p[0][1], p[1][1], p[2][1]}));
  for (std::uint32_t j = j0; j <= j1; ++j)
    for (std::uint32_t i = i0; i <= i1; ++i) {
      const Point2 q = {lattice.coordinate(0, i), lattice.coordinate(1, j)};
      std::array<double, 3> w;  // w[k]: edge opposite corner k
      bool covered = true;
      for (int k = 0; k < 3 && covered; ++k) {
        const Point2& from = p[static_cast<std::size_t>((k + 1) % 3)];
        const Point2& to = p[static_cast<std::size_t>((k + 2) % 3)];
        w[static_cast<std::size_t>(k)] = edgeFunction(from, to, q);
        covered = ownsPoint(w[static_cast<std::size_t>(k)], area, from, to);
      }
      const double sum = w[0] + w[1] + w[2];  // the area again, up to rounding
      if (!covered || sum == 0.0) continue;
      const double depth = (w[0] * A[a] + w[1] * B[a] + w[2] * C[a]) / sum;
      out.push_back({lattice.index(i, j), depth, area > 0.0 ? 1 : -1});
    }
}

/// The intervals of one line from its sorted crossings [c, end): crossings
/// at one depth are applied together, so their order does not matter and
/// no interval is empty. Where an open mesh leaves the winding number
/// non-zero, the last interval never ends. Returns the line's overlap.
double appendIntervals(const Crossing* c, const Crossing* end, std::vector<Interval>& out) {
  int winding = 0;
  double overlap = 0.0;
  while (c != end) {
    const double depth = c->depth;
    const int before = winding;
    for (; c != end && c->depth == depth; ++c) winding += c->sign;
    if (before == 0 && winding != 0)
      out.push_back({depth, std::numeric_limits<double>::infinity()});
    if (before != 0 && winding == 0) out.back().exit = depth;
    if (std::abs(winding) > 1 && c != end) overlap += (std::abs(winding) - 1) * (c->depth - depth);
  }
  return overlap;
}

void checkInput(const TriangleMesh& mesh, const LineLattice& lattice) {
  if (lattice.axis < 0 || lattice.axis > 2)
    throw InvalidArgument("lattice.axis", "must be 0, 1 or 2, got " + std::to_string(lattice.axis));
  if (!(lattice.spacing > 0.0) || !std::isfinite(lattice.spacing))
    throw InvalidArgument("lattice.spacing", "must be positive and finite");
  if (!lattice.origin.allFinite()) throw InvalidArgument("lattice.origin", "must be finite");
  if (!mesh.vertices.allFinite()) throw InvalidArgument("mesh", "has non-finite vertices");
  if (mesh.triangles.rows() > 0 &&
      static_cast<Eigen::Index>(mesh.triangles.maxCoeff()) >= mesh.vertices.rows())
    throw InvalidArgument("mesh", "a triangle indexes a vertex that does not exist");
}

}  // namespace

bool WindingLines::inside(std::size_t line, double c) const {
  // The first interval that does not end below c is the only candidate.
  const Interval* i = std::lower_bound(begin(line), end(line), c,
                                       [](const Interval& s, double x) { return s.exit < x; });
  return i != end(line) && i->enter < c;
}

double WindingLines::length(std::size_t line, double lo, double hi) const {
  double total = 0.0;
  for (const Interval* i = begin(line); i != end(line); ++i)
    total += std::max(0.0, std::min(hi, i->exit) - std::max(lo, i->enter));
  return total;
}

WindingLines windingLines(const TriangleMesh& mesh, const LineLattice& lattice) {
  checkInput(mesh, lattice);
  WindingLines out;
  out.lattice = lattice;
  out.first.assign(lattice.lines() + 1, 0);
  out.overlap.assign(lattice.lines(), 0.0);
  if (lattice.lines() == 0) return out;
  std::vector<Crossing> crossings;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    addCrossings(lattice, mesh.vertices.row(mesh.triangles(t, 0)),
                 mesh.vertices.row(mesh.triangles(t, 1)), mesh.vertices.row(mesh.triangles(t, 2)),
                 crossings);
  std::sort(crossings.begin(), crossings.end());
  const Crossing* c = crossings.data();
  const Crossing* const end = c + crossings.size();
  for (std::size_t line = 0; line < lattice.lines(); ++line) {
    const Crossing* next = c;
    while (next != end && next->line == line) ++next;
    out.overlap[line] = appendIntervals(c, next, out.intervals);
    c = next;
    out.first[line + 1] = static_cast<std::uint32_t>(out.intervals.size());
  }
  return out;
}

}  // namespace hfts::db
