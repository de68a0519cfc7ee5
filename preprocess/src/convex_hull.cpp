// CGAL is confined to this file: its headers are heavy.
#include "preprocess/convex_hull.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <map>

namespace hfts::preprocess {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using HullMesh = CGAL::Surface_mesh<Point>;

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
  planes_.resize(faces_.rows(), 4);
  Eigen::Index row = 0;
  for (HullMesh::Face_index f : hull.faces()) {
    int k = 0;
    for (HullMesh::Vertex_index v : CGAL::vertices_around_face(hull.halfedge(f), hull))
      if (k < 3) faces_(row, k++) = index[v];
    const Eigen::Vector3d a = vertices_.row(faces_(row, 0)).transpose();
    const Eigen::Vector3d n = (vertices_.row(faces_(row, 1)).transpose() - a)
                                  .cross(vertices_.row(faces_(row, 2)).transpose() - a)
                                  .normalized();
    planes_.row(row) << n.transpose(), -n.dot(a);
    ++row;
  }
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
