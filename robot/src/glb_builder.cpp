#include "glb_builder.h"

#include <assimp/Exporter.hpp>

#include <stdexcept>

#include "robot/primitive_meshes.h"

namespace hfts::robot::glb {
namespace {

aiMaterial* material(const char* name, float r, float g, float b) {
  auto* m = new aiMaterial;
  const aiString label(name);
  m->AddProperty(&label, AI_MATKEY_NAME);
  const aiColor4D colour(r, g, b, 1.0f);
  m->AddProperty(&colour, 1, AI_MATKEY_COLOR_DIFFUSE);
  m->AddProperty(&colour, 1, AI_MATKEY_BASE_COLOR);
  return m;
}

aiVector3D point(const Eigen::Vector3d& p) {
  return {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())};
}

aiMesh* toAiMesh(const Part& part) {
  auto* mesh = new aiMesh;
  mesh->mName = part.name;
  mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  mesh->mMaterialIndex = part.material;
  mesh->mNumVertices = static_cast<unsigned>(part.mesh.vertices.rows());
  mesh->mVertices = new aiVector3D[mesh->mNumVertices];
  for (unsigned v = 0; v < mesh->mNumVertices; ++v)
    mesh->mVertices[v] = point(part.mesh.vertices.row(v).transpose());
  mesh->mNumFaces = static_cast<unsigned>(part.mesh.triangles.rows());
  mesh->mFaces = new aiFace[mesh->mNumFaces];
  for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
    mesh->mFaces[f].mNumIndices = 3;
    mesh->mFaces[f].mIndices = new unsigned[3];
    for (int k = 0; k < 3; ++k) mesh->mFaces[f].mIndices[k] = part.mesh.triangles(f, k);
  }
  return mesh;
}

}  // namespace

TriangleMesh transformed(TriangleMesh mesh, const Eigen::Isometry3d& pose) {
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v)
    mesh.vertices.row(v) = (pose * Eigen::Vector3d(mesh.vertices.row(v))).transpose();
  return mesh;
}

TriangleMesh primitiveMesh(int type, const Eigen::Vector3d& size) {
  if (type == 0) return boxMesh(size);
  if (type == 1) return cylinderMesh(size.x(), size.y());
  return sphereMesh(size.x());
}

unsigned linkMaterial(const RobotModel& model, std::size_t l) {
  for (const Fingertip& f : model.fingertips())
    if (static_cast<std::size_t>(f.link) == l) return kFingertip;
  return model.isHandLink(static_cast<int>(l)) ? kHand : kArm;
}

std::vector<Part> environmentParts(const Scene& scene, const db::ObjectGeometry* target,
                                   const Eigen::Isometry3d& targetPose) {
  std::vector<Part> parts;
  for (const Obstacle& o : scene.obstacles) {
    // A cloud's mesh is its occupied voxels' boxes.
    TriangleMesh mesh = o.type == Obstacle::Type::kMesh || o.type == Obstacle::Type::kPoints
                            ? o.mesh
                            : primitiveMesh(static_cast<int>(o.type), o.size);
    parts.push_back({transformed(std::move(mesh), o.pose), kObstacle, o.name});
  }
  if (target != nullptr)
    parts.push_back({transformed({target->mesh_vertices, target->mesh_triangles}, targetPose),
                     kTarget, scene.target_object});
  return parts;
}

Builder::Builder() {
  scene_.mRootNode = new aiNode("scene");
  scene_.mNumMaterials = kMaterials;
  scene_.mMaterials = new aiMaterial*[kMaterials];
  scene_.mMaterials[kArm] = material("arm", 0.95f, 0.45f, 0.05f);
  scene_.mMaterials[kHand] = material("hand", 0.6f, 0.6f, 0.62f);
  scene_.mMaterials[kFingertip] = material("fingertip", 0.15f, 0.15f, 0.18f);
  scene_.mMaterials[kObstacle] = material("obstacle", 0.55f, 0.42f, 0.3f);
  scene_.mMaterials[kTarget] = material("target", 0.1f, 0.55f, 0.95f);
  scene_.mMaterials[kMarker] = material("contact", 0.9f, 0.1f, 0.1f);
  scene_.mMaterials[kPath] = material("path", 0.1f, 0.8f, 0.2f);
  // glTF is y-up: turn the z-up world so viewers show it standing.
  scene_.mRootNode->mTransformation = aiMatrix4x4(1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1);
}

Builder::~Builder() {  // what glb() did not hand over to the scene
  for (aiMesh* m : meshes_) delete m;
  for (aiNode* n : nodes_) delete n;
}

unsigned Builder::addMesh(aiMesh* mesh) {
  meshes_.push_back(mesh);
  return static_cast<unsigned>(meshes_.size() - 1);
}

aiNode* Builder::addNode(const std::string& name, const std::vector<Part>& parts) {
  auto* node = new aiNode(name);
  node->mParent = scene_.mRootNode;
  node->mNumMeshes = static_cast<unsigned>(parts.size());
  node->mMeshes = new unsigned[parts.size()];
  for (std::size_t i = 0; i < parts.size(); ++i) node->mMeshes[i] = addMesh(toAiMesh(parts[i]));
  nodes_.push_back(node);
  return node;
}

aiNode* Builder::addLines(const std::string& name, const std::vector<Eigen::Vector3d>& points,
                          unsigned material) {
  auto* mesh = new aiMesh;
  mesh->mName = name;
  mesh->mPrimitiveTypes = aiPrimitiveType_LINE;
  mesh->mMaterialIndex = material;
  mesh->mNumVertices = static_cast<unsigned>(points.size());
  mesh->mVertices = new aiVector3D[points.size()];
  for (std::size_t v = 0; v < points.size(); ++v) mesh->mVertices[v] = point(points[v]);
  mesh->mNumFaces = static_cast<unsigned>(points.size() / 2);
  mesh->mFaces = new aiFace[mesh->mNumFaces];
  for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
    mesh->mFaces[f].mNumIndices = 2;
    mesh->mFaces[f].mIndices = new unsigned[2]{2 * f, 2 * f + 1};
  }
  auto* node = new aiNode(name);
  node->mParent = scene_.mRootNode;
  node->mNumMeshes = 1;
  node->mMeshes = new unsigned[1]{addMesh(mesh)};
  nodes_.push_back(node);
  return node;
}

std::string Builder::glb(const std::string& what) {
  // Hand the meshes and nodes over to the aiScene, which frees them.
  scene_.mNumMeshes = static_cast<unsigned>(meshes_.size());
  scene_.mMeshes = new aiMesh*[meshes_.size()];
  std::copy(meshes_.begin(), meshes_.end(), scene_.mMeshes);
  meshes_.clear();
  scene_.mRootNode->mNumChildren = static_cast<unsigned>(nodes_.size());
  scene_.mRootNode->mChildren = new aiNode*[nodes_.size()];
  std::copy(nodes_.begin(), nodes_.end(), scene_.mRootNode->mChildren);
  nodes_.clear();
  Assimp::Exporter exporter;
  const aiExportDataBlob* blob = exporter.ExportToBlob(&scene_, "glb2");
  if (blob == nullptr)
    throw std::runtime_error("cannot export " + what + ": " + exporter.GetErrorString());
  return std::string(static_cast<const char*>(blob->data), blob->size);
}

}  // namespace hfts::robot::glb
