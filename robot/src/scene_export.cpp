// assimp scene construction and glTF export.
#include "robot/scene_export.h"

#include <assimp/scene.h>
#include <assimp/Exporter.hpp>

#include <cmath>
#include <stdexcept>

#include "hfts_db/atomic_file.h"
#include "hfts_db/invalid_argument.h"
#include "robot/kinematics.h"

namespace hfts::robot {
namespace {

struct Part {
  TriangleMesh mesh;  // already in the world frame
  unsigned material = 0;
  std::string name;
};

TriangleMesh transformed(TriangleMesh mesh, const Eigen::Isometry3d& pose) {
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v)
    mesh.vertices.row(v) = (pose * Eigen::Vector3d(mesh.vertices.row(v))).transpose();
  return mesh;
}

/// `type`: a CollisionShape::Type or Obstacle::Type value (they agree, see
/// scene.h) other than kMesh.
TriangleMesh primitiveMesh(int type, const Eigen::Vector3d& size) {
  if (type == 0) return boxMesh(size);
  if (type == 1) return cylinderMesh(size.x(), size.y());
  return sphereMesh(size.x());
}

aiMesh* toAiMesh(const Part& part) {
  auto* mesh = new aiMesh;
  mesh->mName = part.name;
  mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  mesh->mMaterialIndex = part.material;
  mesh->mNumVertices = static_cast<unsigned>(part.mesh.vertices.rows());
  mesh->mVertices = new aiVector3D[mesh->mNumVertices];
  for (unsigned v = 0; v < mesh->mNumVertices; ++v)
    mesh->mVertices[v] = aiVector3D(static_cast<float>(part.mesh.vertices(v, 0)),
                                    static_cast<float>(part.mesh.vertices(v, 1)),
                                    static_cast<float>(part.mesh.vertices(v, 2)));
  mesh->mNumFaces = static_cast<unsigned>(part.mesh.triangles.rows());
  mesh->mFaces = new aiFace[mesh->mNumFaces];
  for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
    mesh->mFaces[f].mNumIndices = 3;
    mesh->mFaces[f].mIndices = new unsigned[3];
    for (int k = 0; k < 3; ++k) mesh->mFaces[f].mIndices[k] = part.mesh.triangles(f, k);
  }
  return mesh;
}

aiMaterial* material(const char* name, float r, float g, float b) {
  auto* m = new aiMaterial;
  const aiString label(name);
  m->AddProperty(&label, AI_MATKEY_NAME);
  const aiColor4D colour(r, g, b, 1.0f);
  m->AddProperty(&colour, 1, AI_MATKEY_COLOR_DIFFUSE);
  m->AddProperty(&colour, 1, AI_MATKEY_BASE_COLOR);
  return m;
}

enum Material : unsigned { kArm, kHand, kFingertip, kObstacle, kTarget, kMaterials };

std::vector<Part> robotParts(const RobotModel& model, const Scene& scene,
                             const Eigen::VectorXd& q) {
  const LinkPoses poses = forwardKinematics(model, q);
  std::vector<bool> fingertip(model.links().size(), false);
  for (const Fingertip& f : model.fingertips()) fingertip[static_cast<std::size_t>(f.link)] = true;
  std::vector<Part> parts;
  for (std::size_t l = 0; l < model.links().size(); ++l) {
    const Link& link = model.links()[l];
    const unsigned colour = fingertip[l]                            ? kFingertip
                            : model.isHandLink(static_cast<int>(l)) ? kHand
                                                                    : kArm;
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
  mesh.triangles.resize(2 * rings * n, 3);
  for (int r = 0; r < rings; ++r)
    for (int i = 0; i < n; ++i) {
      const auto a = static_cast<std::uint32_t>(r * n + i);
      const auto b = static_cast<std::uint32_t>(r * n + (i + 1) % n);
      const auto c = a + static_cast<std::uint32_t>(n), d = b + static_cast<std::uint32_t>(n);
      mesh.triangles.row(2 * (r * n + i)) << a, c, b;
      mesh.triangles.row(2 * (r * n + i) + 1) << b, c, d;
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
  for (const Obstacle& o : scene.obstacles) {
    TriangleMesh mesh =
        o.type == Obstacle::Type::kMesh ? o.mesh : primitiveMesh(static_cast<int>(o.type), o.size);
    parts.push_back({transformed(std::move(mesh), o.pose), kObstacle, o.name});
  }
  if (target != nullptr)
    parts.push_back({transformed({target->mesh_vertices, target->mesh_triangles},
                                 targetPose(scene, target->mesh_vertices)),
                     kTarget, scene.target_object});

  aiScene ai;
  ai.mRootNode = new aiNode("scene");
  ai.mNumMaterials = kMaterials;
  ai.mMaterials = new aiMaterial*[kMaterials];
  ai.mMaterials[kArm] = material("arm", 0.95f, 0.45f, 0.05f);
  ai.mMaterials[kHand] = material("hand", 0.6f, 0.6f, 0.62f);
  ai.mMaterials[kFingertip] = material("fingertip", 0.15f, 0.15f, 0.18f);
  ai.mMaterials[kObstacle] = material("obstacle", 0.55f, 0.42f, 0.3f);
  ai.mMaterials[kTarget] = material("target", 0.1f, 0.55f, 0.95f);
  // One named node per part, so viewers list links and obstacles by name.
  ai.mNumMeshes = static_cast<unsigned>(parts.size());
  ai.mMeshes = new aiMesh*[ai.mNumMeshes];
  ai.mRootNode->mNumChildren = ai.mNumMeshes;
  ai.mRootNode->mChildren = new aiNode*[ai.mNumMeshes];
  for (unsigned i = 0; i < ai.mNumMeshes; ++i) {
    ai.mMeshes[i] = toAiMesh(parts[i]);
    auto* node = new aiNode(parts[i].name);
    node->mParent = ai.mRootNode;
    node->mNumMeshes = 1;
    node->mMeshes = new unsigned[1]{i};
    ai.mRootNode->mChildren[i] = node;
  }
  // glTF is y-up: turn the z-up world so viewers show it standing.
  ai.mRootNode->mTransformation = aiMatrix4x4(1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1);

  const std::filesystem::path tmp = db::temporarySibling(path);
  Assimp::Exporter exporter;
  if (exporter.Export(&ai, "glb2", tmp.string()) != AI_SUCCESS) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw std::runtime_error("cannot export '" + path.string() + "': " + exporter.GetErrorString());
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace hfts::robot
