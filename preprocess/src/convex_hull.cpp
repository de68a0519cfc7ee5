// CGAL is confined to this file: its headers are heavy.
#include "preprocess/convex_hull.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
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

/// Twice the area and the outward normal of a hull triangle.
std::pair<double, Eigen::Vector3d> areaNormal(const db::Points3& v, const db::Faces3& f,
                                              Eigen::Index t) {
  const Eigen::Vector3d a = row(v, f(t, 0));
  const Eigen::Vector3d c = (row(v, f(t, 1)) - a).cross(row(v, f(t, 2)) - a);
  const double norm = c.norm();
  return {norm, norm > 0.0 ? Eigen::Vector3d(c / norm) : Eigen::Vector3d::Zero()};
}

/// Groups edge-adjacent coplanar triangles (one polygonal hull facet each).
/// Slivers (three collinear points, which CGAL emits where hull points lie
/// on a line) have no plane and join no group: they would join whichever
/// facet the triangulation put them next to.
std::vector<std::vector<Eigen::Index>> coplanarGroups(const db::Points3& v, const db::Faces3& f,
                                                      double tolerance, double sliver) {
  std::vector<Eigen::Index> parent(static_cast<std::size_t>(f.rows()));
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<Eigen::Index>(i);
  std::function<Eigen::Index(Eigen::Index)> find = [&](Eigen::Index i) {
    auto& p = parent[static_cast<std::size_t>(i)];
    return p == i ? i : (p = find(p));
  };
  const auto onPlane = [&](Eigen::Index t, Eigen::Index other) {
    const Eigen::Vector3d n = areaNormal(v, f, t).second, a = row(v, f(t, 0));
    for (int j = 0; j < 3; ++j)
      if (std::abs(n.dot(row(v, f(other, j)) - a)) > tolerance) return false;
    return true;
  };
  std::vector<bool> proper(static_cast<std::size_t>(f.rows()));
  for (Eigen::Index t = 0; t < f.rows(); ++t)
    proper[static_cast<std::size_t>(t)] = areaNormal(v, f, t).first > sliver;
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
      if (onPlane(t, other->second) && onPlane(other->second, t))
        parent[static_cast<std::size_t>(find(t))] = find(other->second);
    }
  }
  std::map<Eigen::Index, std::vector<Eigen::Index>> groups;
  for (Eigen::Index t = 0; t < f.rows(); ++t)
    if (proper[static_cast<std::size_t>(t)]) groups[find(t)].push_back(t);
  std::vector<std::vector<Eigen::Index>> out;
  for (auto& [root, members] : groups) out.push_back(std::move(members));
  return out;
}

/// The convex polygon of the hull vertices that lie on a facet's plane,
/// counter-clockwise seen from outside, starting at its smallest index;
/// points on its edges are kept, so both facets at an edge hold the same
/// points. A function of the points and the plane alone, not of CGAL's
/// triangulation.
std::vector<std::uint32_t> facetPolygon(const db::Points3& v, const Eigen::Vector3d& normal,
                                        const Eigen::Vector3d& origin, double tolerance) {
  const Eigen::Vector3d u = normal.unitOrthogonal(), w = normal.cross(u);
  std::vector<std::uint32_t> on;
  for (Eigen::Index i = 0; i < v.rows(); ++i)
    if (std::abs(normal.dot(row(v, static_cast<std::uint32_t>(i)) - origin)) <= tolerance)
      on.push_back(static_cast<std::uint32_t>(i));
  if (on.size() < 3) return {};
  const auto at = [&](std::uint32_t i) {
    const Eigen::Vector3d d = row(v, i) - origin;
    return Eigen::Vector2d(d.dot(u), d.dot(w));
  };
  std::sort(on.begin(), on.end(), [&](std::uint32_t a, std::uint32_t b) {
    const Eigen::Vector2d p = at(a), q = at(b);
    return p.x() < q.x() || (p.x() == q.x() && (p.y() < q.y() || (p.y() == q.y() && a < b)));
  });
  // Andrew's monotone chain; a point is dropped only when it lies more
  // than the tolerance inside, so points in a row (up to rounding) stay.
  const auto inside = [&](std::uint32_t o, std::uint32_t a, std::uint32_t b) {
    const Eigen::Vector2d p = at(a) - at(o), q = at(b) - at(o);
    return p.x() * q.y() - p.y() * q.x() < -tolerance * p.norm();
  };
  std::vector<std::uint32_t> hull;
  for (int pass = 0; pass < 2; ++pass) {
    const std::size_t base = hull.size();
    for (std::uint32_t i : on) {
      while (hull.size() >= base + 2 && inside(hull[hull.size() - 2], hull.back(), i))
        hull.pop_back();
      hull.push_back(i);
    }
    hull.pop_back();  // the last point starts the other chain
    std::reverse(on.begin(), on.end());
  }
  std::sort(hull.begin(), hull.end());
  hull.erase(std::unique(hull.begin(), hull.end()), hull.end());
  // Back into boundary order around the centroid (the chains above keep
  // collinear points, but in a convex polygon the angle orders them too).
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (std::uint32_t i : hull) centre += at(i);
  centre /= static_cast<double>(hull.size());
  const auto angle = [&](std::uint32_t i) {
    const Eigen::Vector2d d = at(i) - centre;
    return std::atan2(d.y(), d.x());
  };
  std::sort(hull.begin(), hull.end(), [&](std::uint32_t a, std::uint32_t b) {
    const double p = angle(a), q = angle(b);
    return p < q || (p == q && a < b);
  });
  std::rotate(hull.begin(), std::min_element(hull.begin(), hull.end()), hull.end());
  return hull.size() >= 3 ? hull : std::vector<std::uint32_t>{};
}

/// CGAL's output order, and its triangulation of coplanar facets, depend
/// on memory addresses. Sorting the vertices and triangulating every
/// facet (the hull points on its plane) as a fan from its smallest vertex
/// makes the stored hull a function of the input points alone
/// (byte-identical databases).
void canonicalize(db::Points3& vertices, db::Faces3& faces) {
  sortVertices(vertices, faces);
  const double extent = (vertices.colwise().maxCoeff() - vertices.colwise().minCoeff()).norm();
  const double tolerance = 1e-7 * extent, sliver = 1e-12 * extent * extent;
  std::set<std::vector<std::uint32_t>> facets;
  std::vector<std::array<std::uint32_t, 3>> list;
  for (const auto& group : coplanarGroups(vertices, faces, tolerance, sliver)) {
    // The facet's plane from its largest triangle (the best conditioned).
    Eigen::Index largest = group.front();
    for (Eigen::Index t : group)
      if (areaNormal(vertices, faces, t).first > areaNormal(vertices, faces, largest).first)
        largest = t;
    const std::vector<std::uint32_t> polygon =
        facetPolygon(vertices, areaNormal(vertices, faces, largest).second,
                     row(vertices, faces(largest, 0)), tolerance);
    if (polygon.empty() || !facets.insert(polygon).second) continue;  // one facet, two groups
    for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
      const std::array<std::uint32_t, 3> t{polygon[0], polygon[i], polygon[i + 1]};
      const double area = (row(vertices, t[1]) - row(vertices, t[0]))
                              .cross(row(vertices, t[2]) - row(vertices, t[0]))
                              .norm();
      if (area > sliver) list.push_back(t);  // skip collinear fan slivers
    }
  }
  std::sort(list.begin(), list.end());
  faces.resize(static_cast<Eigen::Index>(list.size()), 3);
  for (std::size_t i = 0; i < list.size(); ++i)
    for (int k = 0; k < 3; ++k)
      faces(static_cast<Eigen::Index>(i), k) = list[i][static_cast<std::size_t>(k)];
}

}  // namespace

ConvexHull::ConvexHull(const Vertices& points, const std::string& what) {
  std::vector<Point> input;
  input.reserve(static_cast<std::size_t>(points.rows()));
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    input.emplace_back(points(i, 0), points(i, 1), points(i, 2));
  HullMesh hull;
  CGAL::convex_hull_3(input.begin(), input.end(), hull);
  if (hull.number_of_faces() < 4)
    throw MeshError(what + ": the convex hull has no volume (all points in one plane)");

  std::map<HullMesh::Vertex_index, std::uint32_t> index;
  vertices_.resize(static_cast<Eigen::Index>(hull.number_of_vertices()), 3);
  for (HullMesh::Vertex_index v : hull.vertices()) {
    const auto row = static_cast<std::uint32_t>(index.size());
    index[v] = row;
    const Point& p = hull.point(v);
    vertices_.row(row) << p.x(), p.y(), p.z();
  }
  faces_.resize(static_cast<Eigen::Index>(hull.number_of_faces()), 3);
  Eigen::Index face = 0;
  for (HullMesh::Face_index f : hull.faces()) {
    int k = 0;
    for (HullMesh::Vertex_index v : CGAL::vertices_around_face(hull.halfedge(f), hull))
      if (k < 3) faces_(face, k++) = index[v];
    ++face;
  }
  canonicalize(vertices_, faces_);
  planes_.resize(faces_.rows(), 4);
  for (Eigen::Index row = 0; row < faces_.rows(); ++row) {
    const Eigen::Vector3d a = vertices_.row(faces_(row, 0)).transpose();
    const Eigen::Vector3d n = (vertices_.row(faces_(row, 1)).transpose() - a)
                                  .cross(vertices_.row(faces_(row, 2)).transpose() - a)
                                  .normalized();
    planes_.row(row) << n.transpose(), -n.dot(a);
  }
  bvh_ = std::make_unique<TriangleBvh>(TriangleMesh{vertices_, faces_});
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

SolidProperties solidProperties(const TriangleMesh& mesh) {
  // Tetrahedra against a point near the mesh keep the sums well conditioned.
  const Eigen::Vector3d origin = mesh.vertices.colwise().mean().transpose();
  double volume6 = 0.0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(t, 0)).transpose() - origin;
    const Eigen::Vector3d b = mesh.vertices.row(mesh.triangles(t, 1)).transpose() - origin;
    const Eigen::Vector3d c = mesh.vertices.row(mesh.triangles(t, 2)).transpose() - origin;
    const double v6 = a.dot(b.cross(c));
    volume6 += v6;
    moment += v6 * (a + b + c) / 4.0;
  }
  SolidProperties out;
  out.volume = std::abs(volume6) / 6.0;
  out.centroid = volume6 != 0.0 ? Eigen::Vector3d(origin + moment / volume6) : origin;
  return out;
}

db::ObjectGeometry objectGeometry(const TriangleMesh& mesh, bool closed, const ConvexHull& hull) {
  db::ObjectGeometry g;
  g.hull_vertices = hull.vertices();
  g.hull_faces = hull.faces();
  g.mesh_vertices = mesh.vertices;
  g.mesh_triangles = mesh.triangles;
  g.closed = closed;
  if (closed) {
    const SolidProperties solid = solidProperties(mesh);
    g.volume = solid.volume;
    g.center_of_mass = solid.centroid;
  } else {
    g.center_of_mass = hull.centroid();
  }
  // The farthest surface point from any point is a hull vertex.
  g.rho = (hull.vertices().rowwise() - g.center_of_mass.transpose()).rowwise().norm().maxCoeff();
  g.bbox_min = mesh.vertices.colwise().minCoeff().transpose();
  g.bbox_max = mesh.vertices.colwise().maxCoeff().transpose();
  return g;
}

}  // namespace hfts::preprocess
