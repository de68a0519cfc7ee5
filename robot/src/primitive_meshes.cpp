#include "robot/primitive_meshes.h"

#include <cmath>

namespace hfts::robot {

TriangleMesh cylinderMesh(double radius, double length, int segments) {
  TriangleMesh mesh;
  const int n = segments;
  mesh.vertices.resize(2 * n + 2, 3);
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * i / n;
    mesh.vertices.row(i) << radius * std::cos(a), radius * std::sin(a), -length / 2;
    mesh.vertices.row(n + i) << radius * std::cos(a), radius * std::sin(a), length / 2;
  }
  mesh.vertices.row(2 * n) << 0, 0, -length / 2;
  mesh.vertices.row(2 * n + 1) << 0, 0, length / 2;
  mesh.triangles.resize(4 * n, 3);
  for (int i = 0; i < n; ++i) {
    const auto a = static_cast<std::uint32_t>(i), b = static_cast<std::uint32_t>((i + 1) % n);
    const auto un = static_cast<std::uint32_t>(n);
    mesh.triangles.row(4 * i) << a, b, un + b;
    mesh.triangles.row(4 * i + 1) << a, un + b, un + a;
    mesh.triangles.row(4 * i + 2) << 2 * un, b, a;
    mesh.triangles.row(4 * i + 3) << 2 * un + 1, un + a, un + b;
  }
  return mesh;
}

TriangleMesh sphereMesh(double radius, int segments) {
  TriangleMesh mesh;
  const int rings = segments / 2, n = segments;
  mesh.vertices.resize((rings + 1) * n, 3);
  for (int r = 0; r <= rings; ++r)
    for (int i = 0; i < n; ++i) {
      const double theta = M_PI * r / rings, phi = 2.0 * M_PI * i / n;
      mesh.vertices.row(r * n + i) << radius * std::sin(theta) * std::cos(phi),
          radius * std::sin(theta) * std::sin(phi), radius * std::cos(theta);
    }
  // Each band between two rings is a strip of quads, but at the poles a
  // ring is one point: there only the triangle with a real edge is kept.
  mesh.triangles.resize(2 * (rings - 1) * n, 3);
  Eigen::Index t = 0;
  for (int r = 0; r < rings; ++r)
    for (int i = 0; i < n; ++i) {
      const auto a = static_cast<std::uint32_t>(r * n + i);
      const auto b = static_cast<std::uint32_t>(r * n + (i + 1) % n);
      const auto c = a + static_cast<std::uint32_t>(n), d = b + static_cast<std::uint32_t>(n);
      if (r > 0) mesh.triangles.row(t++) << a, c, b;
      if (r + 1 < rings) mesh.triangles.row(t++) << b, c, d;
    }
  return mesh;
}

}  // namespace hfts::robot
