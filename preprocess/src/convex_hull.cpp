// CGAL is confined to this file: its headers are heavy.
#include "preprocess/convex_hull.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <set>

namespace hfts::preprocess {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using HullMesh = CGAL::Surface_mesh<Point>;

Eigen::Vector3d row(const db::Points3& v, std::uint32_t i) {
  return v.row(i).transpose();
}

/// Sorts the vertices lexicographically and renumbers the faces.
void sortVertices(db::Points3& vertices, db::Faces3& faces) {
  std::vector<std::uint32_t> order(static_cast<std::size_t>(vertices.rows()));
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  auto key = [&](std::uint32_t i) {
    return std::array<double, 3>{vertices(i, 0), vertices(i, 1), vertices(i, 2)};
  };
  std::sort(order.begin(), order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
  std::vector<std::uint32_t> rank(order.size());
  db::Points3 sorted(vertices.rows(), 3);
  for (std::uint32_t i = 0; i < order.size(); ++i) {
    rank[order[i]] = i;
    sorted.row(i) = vertices.row(order[i]);
  }
  vertices = std::move(sorted);
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) faces(f, k) = rank[faces(f, k)];
}

Point point(const db::Points3& v, std::uint32_t i) {
  return {v(i, 0), v(i, 1), v(i, 2)};
}

/// Whether a hull triangle's corners are exactly collinear (CGAL emits
/// such slivers where hull points lie in a row).
bool isSliver(const db::Points3& v, const db::Faces3& f, Eigen::Index t) {
  return CGAL::collinear(point(v, f(t, 0)), point(v, f(t, 1)), point(v, f(t, 2)));
}

/// Whether point p lies exactly on the plane of hull triangle t.
bool onPlaneOf(const db::Points3& v, const db::Faces3& f, Eigen::Index t, std::uint32_t p) {
  return CGAL::orientation(point(v, f(t, 0)), point(v, f(t, 1)), point(v, f(t, 2)), point(v, p)) ==
         CGAL::COPLANAR;
}

/// One representative triangle per facet: the triangles of a facet are
/// edge-adjacent and exactly coplanar (exact predicates, so the facets are
/// those of the point set, not of CGAL's triangulation or a tolerance).
/// Slivers have no plane and represent nothing.
std::vector<Eigen::Index> facetRepresentatives(const db::Points3& v, const db::Faces3& f) {
  std::vector<Eigen::Index> parent(static_cast<std::size_t>(f.rows()));
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<Eigen::Index>(i);
  std::function<Eigen::Index(Eigen::Index)> find = [&](Eigen::Index i) {
    auto& p = parent[static_cast<std::size_t>(i)];
    return p == i ? i : (p = find(p));
  };
  std::vector<bool> proper(static_cast<std::size_t>(f.rows()));
  for (Eigen::Index t = 0; t < f.rows(); ++t)
    proper[static_cast<std::size_t>(t)] = !isSliver(v, f, t);
  std::map<std::pair<std::uint32_t, std::uint32_t>, Eigen::Index> edgeOwner;
  for (Eigen::Index t = 0; t < f.rows(); ++t) {
    if (!proper[static_cast<std::size_t>(t)]) continue;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t p = f(t, k), q = f(t, (k + 1) % 3);
      const auto other = edgeOwner.find({q, p});  // the neighbour runs the edge backwards
      if (other == edgeOwner.end()) {
        edgeOwner[{p, q}] = t;
        continue;
      }
      if (onPlaneOf(v, f, other->second, f(t, (k + 2) % 3)))
        parent[static_cast<std::size_t>(find(t))] = find(other->second);
    }
  }
  std::set<Eigen::Index> roots;
  for (Eigen::Index t = 0; t < f.rows(); ++t)
    if (proper[static_cast<std::size_t>(t)]) roots.insert(find(t));
  return {roots.begin(), roots.end()};
}

/// The facet of the hull in the plane of triangle t: the corners of the
/// convex polygon of the hull points on that plane (points on its edges or
/// inside are not corners), counter-clockwise seen from outside, starting
/// at the smallest index. Exact predicates make it a function of the
/// points alone.
std::vector<std::uint32_t> facetPolygon(const db::Points3& v, const db::Faces3& f, Eigen::Index t) {
  using Point2 = Kernel::Point_2;
  // Dropping the normal's largest coordinate projects the plane one to one
  // and keeps orientation up to one sign, fixed below with t itself.
  const Eigen::Vector3d a = row(v, f(t, 0));
  const Eigen::Vector3d normal = (row(v, f(t, 1)) - a).cross(row(v, f(t, 2)) - a);
  Eigen::Index drop = 0;
  normal.cwiseAbs().maxCoeff(&drop);
  const int x = drop == 0 ? 1 : 0, y = drop == 2 ? 1 : 2;
  const auto at = [&](std::uint32_t i) { return Point2(v(i, x), v(i, y)); };
  const bool flipped = CGAL::orientation(at(f(t, 0)), at(f(t, 1)), at(f(t, 2))) != CGAL::LEFT_TURN;

  std::vector<std::uint32_t> on;
  for (Eigen::Index i = 0; i < v.rows(); ++i)
    if (onPlaneOf(v, f, t, static_cast<std::uint32_t>(i)))
      on.push_back(static_cast<std::uint32_t>(i));
  std::sort(on.begin(), on.end(), [&](std::uint32_t p, std::uint32_t q) { return at(p) < at(q); });
  // Andrew's monotone chain, counter-clockwise in the projection; a point
  // stays only where the boundary turns strictly left.
  std::vector<std::uint32_t> corners;
  for (int pass = 0; pass < 2; ++pass) {
    const std::size_t base = corners.size();
    for (std::uint32_t i : on) {
      while (corners.size() >= base + 2 &&
             CGAL::orientation(at(corners[corners.size() - 2]), at(corners.back()), at(i)) !=
                 CGAL::LEFT_TURN)
        corners.pop_back();
      corners.push_back(i);
    }
    corners.pop_back();  // the last point starts the other chain
    std::reverse(on.begin(), on.end());
  }
  if (flipped) std::reverse(corners.begin(), corners.end());
  std::rotate(corners.begin(), std::min_element(corners.begin(), corners.end()), corners.end());
  return corners.size() >= 3 ? corners : std::vector<std::uint32_t>{};
}

/// Keeps the vertices the faces use (in their order) and renumbers the
/// faces: hull points on a facet's edge or inside it are not corners.
void dropUnusedVertices(db::Points3& vertices, db::Faces3& faces) {
  std::vector<std::int64_t> renumber(static_cast<std::size_t>(vertices.rows()), -1);
  for (Eigen::Index t = 0; t < faces.rows(); ++t)
    for (int k = 0; k < 3; ++k) renumber[faces(t, k)] = 0;
  std::int64_t next = 0;
  db::Points3 used(vertices.rows(), 3);
  for (std::size_t i = 0; i < renumber.size(); ++i)
    if (renumber[i] == 0) {
      used.row(next) = vertices.row(static_cast<Eigen::Index>(i));
      renumber[i] = next++;
    }
  used.conservativeResize(next, 3);
  vertices = std::move(used);
  for (Eigen::Index t = 0; t < faces.rows(); ++t)
    for (int k = 0; k < 3; ++k) faces(t, k) = static_cast<std::uint32_t>(renumber[faces(t, k)]);
}

/// CGAL's output order, its triangulation of coplanar facets and whether
/// it keeps points on a facet depend on memory addresses. Sorting the
/// vertices, keeping the facets' corners and triangulating every facet as
/// a fan from its smallest corner makes the stored hull a function of the
/// input points alone (byte-identical databases).
void canonicalize(db::Points3& vertices, db::Faces3& faces) {
  sortVertices(vertices, faces);
  std::set<std::vector<std::uint32_t>> facets;
  for (Eigen::Index t : facetRepresentatives(vertices, faces)) {
    std::vector<std::uint32_t> polygon = facetPolygon(vertices, faces, t);
    if (!polygon.empty()) facets.insert(std::move(polygon));  // a set: one facet, two groups
  }
  std::vector<std::array<std::uint32_t, 3>> list;
  for (const auto& polygon : facets)
    for (std::size_t i = 1; i + 1 < polygon.size(); ++i)
      list.push_back({polygon[0], polygon[i], polygon[i + 1]});
  std::sort(list.begin(), list.end());
  faces.resize(static_cast<Eigen::Index>(list.size()), 3);
  for (std::size_t i = 0; i < list.size(); ++i)
    for (int k = 0; k < 3; ++k)
      faces(static_cast<Eigen::Index>(i), k) = list[i][static_cast<std::size_t>(k)];
  dropUnusedVertices(vertices, faces);
}

}  // namespace

/// The sine of a fan triangle's angle below which it is a sliver.
constexpr double kSliverSine = 1e-9;

db::ConvexPiece canonicalHull(const Vertices& points, const std::string& what) {
  // Repeated points go first: CGAL keeps a facet's copies of one corner
  // apart, and a fan from them has a degenerate first triangle whose plane
  // is any plane (seen on the points and shadows of a partial view).
  std::vector<std::array<double, 3>> unique;
  unique.reserve(static_cast<std::size_t>(points.rows()));
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    unique.push_back({points(i, 0), points(i, 1), points(i, 2)});
  std::sort(unique.begin(), unique.end());
  unique.erase(std::unique(unique.begin(), unique.end()), unique.end());
  std::vector<Point> input;
  input.reserve(unique.size());
  for (const auto& p : unique) input.emplace_back(p[0], p[1], p[2]);
  HullMesh hull;
  CGAL::convex_hull_3(input.begin(), input.end(), hull);
  if (hull.number_of_faces() < 4)
    throw MeshError(what + ": the convex hull has no volume (all points in one plane)");

  db::ConvexPiece out;
  std::map<HullMesh::Vertex_index, std::uint32_t> index;
  out.vertices.resize(static_cast<Eigen::Index>(hull.number_of_vertices()), 3);
  for (HullMesh::Vertex_index v : hull.vertices()) {
    const auto row = static_cast<std::uint32_t>(index.size());
    index[v] = row;
    const Point& p = hull.point(v);
    out.vertices.row(row) << p.x(), p.y(), p.z();
  }
  out.faces.resize(static_cast<Eigen::Index>(hull.number_of_faces()), 3);
  Eigen::Index face = 0;
  for (HullMesh::Face_index f : hull.faces()) {
    int k = 0;
    for (HullMesh::Vertex_index v : CGAL::vertices_around_face(hull.halfedge(f), hull))
      if (k < 3) out.faces(face, k++) = index[v];
    ++face;
  }
  canonicalize(out.vertices, out.faces);
  return out;
}

ConvexHull::ConvexHull(const Vertices& points, const std::string& what) {
  db::ConvexPiece hull = canonicalHull(points, what);
  vertices_ = std::move(hull.vertices);
  faces_ = std::move(hull.faces);
  planes_.resize(faces_.rows(), 4);
  for (Eigen::Index row = 0; row < faces_.rows(); ++row) {
    const Eigen::Vector3d a = vertices_.row(faces_(row, 0)).transpose();
    const Eigen::Vector3d ab = vertices_.row(faces_(row, 1)).transpose() - a;
    const Eigen::Vector3d ac = vertices_.row(faces_(row, 2)).transpose() - a;
    const Eigen::Vector3d n = ab.cross(ac);
    // A sliver of a facet's fan (corners a rounding error off one line, as
    // on the dense points and shadows of a partial view) has no plane of
    // its own; its facet's other triangles carry the facet's.
    if (n.norm() <= kSliverSine * ab.norm() * ac.norm()) {
      planes_.row(row) << 0.0, 0.0, 0.0, -std::numeric_limits<double>::infinity();
      continue;
    }
    planes_.row(row) << n.normalized().transpose(), -n.normalized().dot(a);
  }
  bvh_ = std::make_unique<db::TriangleBvh>(TriangleMesh{vertices_, faces_});
}

ConvexHull::ConvexHull(ConvexHull&&) noexcept = default;
ConvexHull::~ConvexHull() = default;

bool ConvexHull::isShallow(const Eigen::Vector3d& p, double limit) const {
  // Inside a convex polytope the distance to the boundary surface is the
  // depth, and the BVH finds whether any hull triangle is that close.
  return bvh_->isWithin(p, limit);
}

double ConvexHull::depth(const Eigen::Vector3d& p) const {
  // Inside a convex polytope the distance to the boundary is the distance
  // to the nearest facet plane.
  return -(planes_.leftCols<3>() * p + planes_.col(3)).maxCoeff();
}

Eigen::Vector3d ConvexHull::centroid() const {
  TriangleMesh mesh{vertices_, faces_};
  return solidProperties(mesh).centroid;
}

}  // namespace hfts::preprocess
