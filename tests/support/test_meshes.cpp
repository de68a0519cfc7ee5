#include "test_meshes.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

#include "hfts_db/triangle_bvh.h"

namespace hfts::test {

db::ObjectGeometry meshObject(const TriangleMesh& mesh) {
  db::ObjectGeometry g;
  g.mesh_vertices = mesh.vertices;
  g.mesh_triangles = mesh.triangles;
  return g;
}

TriangleMesh cube(double size, const Eigen::Vector3d& center) {
  TriangleMesh mesh;
  mesh.vertices.resize(8, 3);
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d corner((i & 1) ? 0.5 : -0.5, (i & 2) ? 0.5 : -0.5, (i & 4) ? 0.5 : -0.5);
    mesh.vertices.row(i) = (center + size * corner).transpose();
  }
  mesh.triangles.resize(12, 3);
  mesh.triangles << 0, 2, 1, 1, 2, 3,  // z-
      4, 5, 6, 5, 7, 6,                // z+
      0, 1, 4, 1, 5, 4,                // y-
      2, 6, 3, 3, 6, 7,                // y+
      0, 4, 2, 2, 4, 6,                // x-
      1, 3, 5, 3, 7, 5;                // x+
  return mesh;
}

TriangleMesh block(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  TriangleMesh mesh = cube(1.0, Eigen::Vector3d::Constant(0.5));  // corners 0 and 1
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v)
    for (int c = 0; c < 3; ++c) mesh.vertices(v, c) = mesh.vertices(v, c) == 0.0 ? lo[c] : hi[c];
  return mesh;
}

TriangleMesh merged(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh out;
  out.vertices.resize(a.vertices.rows() + b.vertices.rows(), 3);
  out.vertices << a.vertices, b.vertices;
  out.triangles.resize(a.triangles.rows() + b.triangles.rows(), 3);
  Triangles shifted = b.triangles.array() + static_cast<std::uint32_t>(a.vertices.rows());
  out.triangles << a.triangles, shifted;
  return out;
}

TriangleMesh flipped(TriangleMesh mesh) {
  mesh.triangles.col(1).swap(mesh.triangles.col(2));
  return mesh;
}

TriangleMesh square(double size, double z) {
  TriangleMesh mesh;
  mesh.vertices.resize(4, 3);
  const double h = size / 2;
  mesh.vertices << -h, -h, z, h, -h, z, h, h, z, -h, h, z;
  mesh.triangles.resize(2, 3);
  mesh.triangles << 0, 1, 2, 0, 2, 3;
  return mesh;
}

TriangleMesh revolved(const std::vector<Eigen::Vector2d>& profile, int segments) {
  TriangleMesh mesh;
  std::vector<std::vector<std::uint32_t>> rings;
  std::vector<Eigen::Vector3d> vertices;
  for (const Eigen::Vector2d& rz : profile) {
    std::vector<std::uint32_t> ring;
    for (int j = 0; j < segments; ++j) {
      if (rz.x() <= 0.0 && j > 0) {  // a point on the axis is one vertex
        ring.push_back(ring.front());
        continue;
      }
      const double a = 2.0 * M_PI * j / segments;
      ring.push_back(static_cast<std::uint32_t>(vertices.size()));
      vertices.emplace_back(rz.x() * std::cos(a), rz.x() * std::sin(a), rz.y());
    }
    rings.push_back(ring);
  }
  std::vector<std::array<std::uint32_t, 3>> triangles;
  for (std::size_t i = 0; i + 1 < rings.size(); ++i)
    for (int j = 0; j < segments; ++j) {
      const auto next = static_cast<std::size_t>((j + 1) % segments),
                 at = static_cast<std::size_t>(j);
      const std::uint32_t a = rings[i][at], b = rings[i][next], c = rings[i + 1][next],
                          d = rings[i + 1][at];
      if (a != b && b != c && c != a) triangles.push_back({a, b, c});
      if (a != c && c != d && d != a) triangles.push_back({a, c, d});
    }
  mesh.vertices.resize(static_cast<Eigen::Index>(vertices.size()), 3);
  for (std::size_t i = 0; i < vertices.size(); ++i)
    mesh.vertices.row(static_cast<Eigen::Index>(i)) = vertices[i].transpose();
  mesh.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t i = 0; i < triangles.size(); ++i)
    mesh.triangles.row(static_cast<Eigen::Index>(i)) << triangles[i][0], triangles[i][1],
        triangles[i][2];
  return mesh;
}

TriangleMesh cup(double radius, double height, double wall, double floor) {
  // Rings every 5 mm up the walls, so a removed triangle is a small hole.
  std::vector<Eigen::Vector2d> profile = {{0.0, 0.0}};
  const auto segment = [&](const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
    const int steps = std::max(1, static_cast<int>(std::ceil((to - from).norm() / 0.005)));
    for (int k = 1; k <= steps; ++k) profile.push_back(from + (to - from) * k / steps);
  };
  segment({0.0, 0.0}, {radius, 0.0});
  segment({radius, 0.0}, {radius, height});
  segment({radius, height}, {radius - wall, height});
  segment({radius - wall, height}, {radius - wall, floor});
  segment({radius - wall, floor}, {0.0, floor});
  return revolved(profile, 64);
}

TempDir::TempDir() {
  std::random_device rd;
  path_ = std::filesystem::temp_directory_path() /
          ("hfts-test-" + std::to_string(rd()) + std::to_string(rd()));
  std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::string readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

namespace {

Eigen::Vector3d corner(const TriangleMesh& mesh, Eigen::Index t, int k) {
  return mesh.vertices.row(mesh.triangles(t, k)).transpose();
}

Eigen::Vector3d faceNormal(const TriangleMesh& mesh, Eigen::Index t) {
  return (corner(mesh, t, 1) - corner(mesh, t, 0))
      .cross(corner(mesh, t, 2) - corner(mesh, t, 0))
      .normalized();
}

}  // namespace

void writeBinaryStl(const std::filesystem::path& path, const TriangleMesh& mesh) {
  std::ofstream out(path, std::ios::binary);
  char header[80] = "hfts test mesh";
  out.write(header, 80);
  const auto count = static_cast<std::uint32_t>(mesh.triangles.rows());
  out.write(reinterpret_cast<const char*>(&count), 4);
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    float values[12];
    const Eigen::Vector3d n = faceNormal(mesh, t);
    for (int c = 0; c < 3; ++c) values[c] = static_cast<float>(n[c]);
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) values[3 + 3 * k + c] = static_cast<float>(corner(mesh, t, k)[c]);
    out.write(reinterpret_cast<const char*>(values), sizeof(values));
    const std::uint16_t attribute = 0;
    out.write(reinterpret_cast<const char*>(&attribute), 2);
  }
}

void writeAsciiStl(const std::filesystem::path& path, const TriangleMesh& mesh) {
  std::ofstream out(path);
  out.precision(9);
  out << "solid test\n";
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    out << " facet normal " << faceNormal(mesh, t).transpose() << "\n  outer loop\n";
    for (int k = 0; k < 3; ++k) out << "   vertex " << corner(mesh, t, k).transpose() << "\n";
    out << "  endloop\n endfacet\n";
  }
  out << "endsolid test\n";
}

void writeObj(const std::filesystem::path& path, const TriangleMesh& mesh) {
  std::ofstream out(path);
  out.precision(9);
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v)
    out << "v " << mesh.vertices.row(v) << "\n";
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    out << "f " << (mesh.triangles.row(t).array() + 1) << "\n";
}

void writeAsciiPly(const std::filesystem::path& path, const TriangleMesh& mesh) {
  std::ofstream out(path);
  out.precision(9);
  out << "ply\nformat ascii 1.0\nelement vertex " << mesh.vertices.rows()
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face "
      << mesh.triangles.rows() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) out << mesh.vertices.row(v) << "\n";
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    out << "3 " << mesh.triangles.row(t) << "\n";
}

void writeCollada(const std::filesystem::path& path, const TriangleMesh& mesh) {
  std::ostringstream positions, indices;
  positions.precision(9);
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) positions << mesh.vertices.row(v) << " ";
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) indices << mesh.triangles.row(t) << " ";
  const auto nv = mesh.vertices.rows();
  std::ofstream out(path);
  out << R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_geometries><geometry id="mesh" name="mesh"><mesh>
    <source id="pos"><float_array id="pos-array" count=")"
      << 3 * nv << R"(">)" << positions.str() << R"(</float_array>
      <technique_common><accessor source="#pos-array" count=")"
      << nv
      << R"(" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common>
    </source>
    <vertices id="verts"><input semantic="POSITION" source="#pos"/></vertices>
    <triangles count=")"
      << mesh.triangles.rows() << R"("><input semantic="VERTEX" source="#verts" offset="0"/><p>)"
      << indices.str() << R"(</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="scene"><node id="node"><instance_geometry url="#mesh"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";
}

double bruteForceDistance(const TriangleMesh& mesh, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const Eigen::Vector3d q =
        db::closestPointOnTriangle(p, corner(mesh, t, 0), corner(mesh, t, 1), corner(mesh, t, 2));
    best = std::min(best, (q - p).norm());
  }
  return best;
}

double windingNumber(const TriangleMesh& mesh, const Eigen::Vector3d& p) {
  double sum = 0.0;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    // Van Oosterom and Strackee's solid angle of a triangle.
    const Eigen::Vector3d a = corner(mesh, t, 0) - p, b = corner(mesh, t, 1) - p,
                          c = corner(mesh, t, 2) - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    sum += 2.0 * std::atan2(numerator, denominator);
  }
  return sum / (4.0 * M_PI);
}

std::filesystem::path bundledMeshDir() {
  return std::filesystem::path(HFTS_SOURCE_DIR) / "objects" / "meshes";
}

std::vector<std::filesystem::path> bundledMeshes() {
  std::vector<std::filesystem::path> out;
  for (const auto& entry : std::filesystem::directory_iterator(bundledMeshDir()))
    if (entry.path().extension() != ".json") out.push_back(entry.path());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace hfts::test
