#include "piece_hull.h"

#include <libqhull_r/qhull_ra.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <numeric>

namespace hfts::preprocess {
namespace {

/// Qhull reports a flat input as an error on a FILE; here it means no piece.
FILE* nullStream() {
  static FILE* stream = std::fopen("/dev/null", "w");
  return stream;
}

using Polygon = std::vector<int>;  ///< point ids, counter-clockwise from outside

/// The vertices of a 3-d facet in cyclic order, turned to wind
/// counter-clockwise around its outward normal (Newell's normal decides).
Polygon facetPolygon(qhT* qh, facetT* facet) {
  Polygon ids;
  setT* vertices = qh_facet3vertex(qh, facet);
  vertexT *vertex, **vertexp;
  FOREACHvertex_(vertices) ids.push_back(qh_pointid(qh, vertex->point));
  qh_settempfree(qh, &vertices);
  double n[3] = {0.0, 0.0, 0.0};
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const coordT* a = qh_point(qh, ids[k]);
    const coordT* b = qh_point(qh, ids[(k + 1) % ids.size()]);
    n[0] += (a[1] - b[1]) * (a[2] + b[2]);
    n[1] += (a[2] - b[2]) * (a[0] + b[0]);
    n[2] += (a[0] - b[0]) * (a[1] + b[1]);
  }
  if (n[0] * facet->normal[0] + n[1] * facet->normal[1] + n[2] * facet->normal[2] < 0.0)
    std::reverse(ids.begin(), ids.end());
  return ids;
}

/// The hull's facets as polygons of point ids; none if Qhull fails.
std::vector<Polygon> hullFacets(std::vector<double>& xyz) {
  const auto count = static_cast<int>(xyz.size() / 3);
  std::vector<Polygon> facets;
  if (count < 4) return facets;
  qhT context;
  qhT* qh = &context;
  qh_zero(qh, nullStream());
  char options[] = "qhull";
  if (qh_new_qhull(qh, 3, count, xyz.data(), False, options, nullptr, nullStream()) == 0) {
    facetT* facet;
    FORALLfacets facets.push_back(facetPolygon(qh, facet));
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  return facets;
}

}  // namespace

db::ConvexPiece pieceHull(std::vector<double> xyz) {
  std::vector<Polygon> facets = hullFacets(xyz);
  db::ConvexPiece piece;
  if (facets.empty()) return piece;
  // Number the used points in lexicographic order of their coordinates.
  std::vector<int> used;
  for (const Polygon& f : facets) used.insert(used.end(), f.begin(), f.end());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  const auto at = [&](int id) {
    return std::array<double, 3>{xyz[3 * id], xyz[3 * id + 1], xyz[3 * id + 2]};
  };
  std::stable_sort(used.begin(), used.end(), [&](int a, int b) { return at(a) < at(b); });
  std::vector<std::uint32_t> rank(xyz.size() / 3, 0);
  piece.vertices.resize(static_cast<Eigen::Index>(used.size()), 3);
  for (std::size_t r = 0; r < used.size(); ++r) {
    rank[static_cast<std::size_t>(used[r])] = static_cast<std::uint32_t>(r);
    const std::array<double, 3> p = at(used[r]);
    piece.vertices.row(static_cast<Eigen::Index>(r)) << p[0], p[1], p[2];
  }
  std::vector<std::array<std::uint32_t, 3>> triangles;
  for (Polygon& f : facets) {
    std::vector<std::uint32_t> r(f.size());
    std::transform(f.begin(), f.end(), r.begin(),
                   [&](int id) { return rank[static_cast<std::size_t>(id)]; });
    std::rotate(r.begin(), std::min_element(r.begin(), r.end()), r.end());
    for (std::size_t k = 1; k + 1 < r.size(); ++k) triangles.push_back({r[0], r[k], r[k + 1]});
  }
  std::sort(triangles.begin(), triangles.end());
  piece.faces.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (std::size_t k = 0; k < 3; ++k)
      piece.faces(static_cast<Eigen::Index>(t), static_cast<Eigen::Index>(k)) = triangles[t][k];
  return piece;
}

}  // namespace hfts::preprocess
