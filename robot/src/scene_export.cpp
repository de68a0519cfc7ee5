// assimp scene construction and glTF export.
#include "robot/scene_export.h"

#include <cmath>
#include <stdexcept>

#include "hfts_db/atomic_file.h"
#include "hfts_db/invalid_argument.h"
#include "robot/kinematics.h"

#include "glb_builder.h"

namespace hfts::robot {
namespace {

using namespace glb;

std::vector<Part> robotParts(const RobotModel& model, const Scene& scene,
                             const Eigen::VectorXd& q) {
  const LinkPoses poses = forwardKinematics(model, q);
  std::vector<Part> parts;
  for (std::size_t l = 0; l < model.links().size(); ++l) {
    const Link& link = model.links()[l];
    const unsigned colour = linkMaterial(model, l);
    for (std::size_t s = 0; s < link.shapes.size(); ++s) {
      const CollisionShape& shape = link.shapes[s];
      parts.push_back({transformed(primitiveMesh(static_cast<int>(shape.type), shape.size),
                                   scene.robot_base * poses[l] * shape.origin),
                       colour, link.name + "_" + std::to_string(s)});
    }
  }
  // The fingertip contact points as small spheres, to check the pads.
  const FingertipFrames tips = fingertipFrames(model, poses);
  for (Eigen::Index i = 0; i < tips.positions.cols(); ++i) {
    const Eigen::Isometry3d at(
        Eigen::Translation3d(scene.robot_base * Eigen::Vector3d(tips.positions.col(i))));
    parts.push_back(
        {transformed(sphereMesh(0.005, 12), at), kTarget, "contact_" + std::to_string(i)});
  }
  return parts;
}

}  // namespace

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

void exportSceneGlb(const RobotModel& model, const Scene& scene, const db::ObjectGeometry* target,
                    const Eigen::VectorXd& q, const std::filesystem::path& path) {
  if (q.size() != model.numDofs())
    throw InvalidArgument("configuration", std::to_string(model.numDofs()) +
                                               " values expected, got " + std::to_string(q.size()));
  if (path.extension() != ".glb")
    throw InvalidArgument("path", "'" + path.string() + "' must end in .glb (binary glTF)");
  std::vector<Part> parts = robotParts(model, scene, q);
  for (Part& p : environmentParts(scene, target,
                                  target != nullptr ? targetPose(scene, target->mesh_vertices)
                                                    : Eigen::Isometry3d::Identity()))
    parts.push_back(std::move(p));
  // One named node per part, so viewers list links and obstacles by name.
  Builder builder;
  for (const Part& part : parts) builder.addNode(part.name, {part});
  db::writeFileAtomically(path, builder.glb("'" + path.string() + "'"));
}

}  // namespace hfts::robot
