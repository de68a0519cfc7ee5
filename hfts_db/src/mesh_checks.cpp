// Sanity and topology checks of triangle meshes.
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "hfts_db/triangle_mesh.h"

namespace hfts {
namespace {

Eigen::Vector3d corner(const TriangleMesh& mesh, Eigen::Index t, int k) {
  return mesh.vertices.row(mesh.triangles(t, k)).transpose();
}

double doubleArea(const TriangleMesh& mesh, Eigen::Index t) {
  return (corner(mesh, t, 1) - corner(mesh, t, 0))
      .cross(corner(mesh, t, 2) - corner(mesh, t, 0))
      .norm();
}

/// True when every vertex lies within `tolerance` of one plane.
bool isFlat(const Vertices& v, double tolerance) {
  const Eigen::RowVector3d mean = v.colwise().mean();
  const Eigen::MatrixXd centered = v.rowwise() - mean;
  const Eigen::Matrix3d covariance = centered.transpose() * centered;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  const Eigen::Vector3d normal = solver.eigenvectors().col(0);
  return (centered * normal).cwiseAbs().maxCoeff() <= tolerance;
}

}  // namespace

std::size_t sanitizeMesh(TriangleMesh& mesh, const std::string& what) {
  if (mesh.triangles.rows() == 0 || mesh.vertices.rows() == 0)
    throw MeshError(what + ": contains no triangles");
  if (!mesh.vertices.allFinite()) throw MeshError(what + ": has non-finite vertex coordinates");
  if (mesh.triangles.maxCoeff() >= static_cast<std::uint32_t>(mesh.vertices.rows()))
    throw MeshError(what + ": a triangle indexes a vertex that does not exist");

  const double extent =
      (mesh.vertices.colwise().maxCoeff() - mesh.vertices.colwise().minCoeff()).norm();
  const double minDoubleArea = 1e-12 * extent * extent;
  std::vector<Eigen::Index> kept;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    if (doubleArea(mesh, t) > minDoubleArea) kept.push_back(t);
  if (kept.empty()) throw MeshError(what + ": is degenerate (every triangle has zero area)");
  const std::size_t dropped = static_cast<std::size_t>(mesh.triangles.rows()) - kept.size();
  if (dropped > 0) {
    Triangles compact(static_cast<Eigen::Index>(kept.size()), 3);
    for (std::size_t i = 0; i < kept.size(); ++i)
      compact.row(static_cast<Eigen::Index>(i)) = mesh.triangles.row(kept[i]);
    mesh.triangles = std::move(compact);
  }
  if (isFlat(mesh.vertices, 1e-9 * extent))
    throw MeshError(what + ": is degenerate (all vertices lie in one plane, no volume to grasp)");
  return dropped;
}

MeshTopology analyzeTopology(const TriangleMesh& mesh) {
  // Per undirected edge: how often it is used in each direction.
  struct Use {
    int forward = 0;
    int backward = 0;
  };
  std::unordered_map<std::uint64_t, Use> edges;
  edges.reserve(static_cast<std::size_t>(mesh.triangles.rows()) * 3);
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t a = mesh.triangles(t, k);
      const std::uint64_t b = mesh.triangles(t, (k + 1) % 3);
      Use& use = edges[(std::min(a, b) << 32) | std::max(a, b)];
      (a < b ? use.forward : use.backward) += 1;
    }
  }
  MeshTopology topology;
  for (const auto& [key, use] : edges) {
    const int total = use.forward + use.backward;
    if (total == 1)
      ++topology.boundary_edges;
    else if (total > 2)
      ++topology.non_manifold_edges;
    else if (use.forward != 1)
      ++topology.inconsistent_edges;
  }
  return topology;
}

double surfaceArea(const TriangleMesh& mesh) {
  double twice = 0.0;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) twice += doubleArea(mesh, t);
  return 0.5 * twice;
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

TriangleMesh boxMesh(const Eigen::Vector3d& size) {
  TriangleMesh mesh;
  mesh.vertices.resize(8, 3);
  for (int i = 0; i < 8; ++i)
    mesh.vertices.row(i) << ((i & 1) ? 0.5 : -0.5) * size.x(), ((i & 2) ? 0.5 : -0.5) * size.y(),
        ((i & 4) ? 0.5 : -0.5) * size.z();
  mesh.triangles.resize(12, 3);
  mesh.triangles << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2,
      2, 4, 6, 1, 3, 5, 3, 7, 5;
  return mesh;
}

}  // namespace hfts
