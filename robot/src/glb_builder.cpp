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
  scene_.mMaterials[kPoints] = material("points", 0.55f, 0.15f, 0.75f);
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

aiNode* Builder::addNodeOf(const std::string& name, const std::vector<aiMesh*>& meshes) {
  auto* node = new aiNode(name);
  node->mParent = scene_.mRootNode;
  node->mNumMeshes = static_cast<unsigned>(meshes.size());
  node->mMeshes = new unsigned[meshes.size()];
  for (std::size_t i = 0; i < meshes.size(); ++i) node->mMeshes[i] = addMesh(meshes[i]);
  nodes_.push_back(node);
  return node;
}

aiNode* Builder::addNode(const std::string& name, const std::vector<Part>& parts) {
  std::vector<aiMesh*> meshes;
  for (const Part& part : parts) meshes.push_back(toAiMesh(part));
  return addNodeOf(name, meshes);
}

aiNode* Builder::addPrimitives(const std::string& name, std::vector<aiVector3D> vertices,
                               unsigned perFace, aiPrimitiveType type, unsigned material) {
  auto* mesh = new aiMesh;
  mesh->mName = name;
  mesh->mPrimitiveTypes = type;
  mesh->mMaterialIndex = material;
  mesh->mNumVertices = static_cast<unsigned>(vertices.size());
  mesh->mVertices = new aiVector3D[vertices.size()];
  std::copy(vertices.begin(), vertices.end(), mesh->mVertices);
  // Points need no faces: without them the exporter writes no indices
  // (glTF draws every vertex), a quarter of a cloud's bytes.
  if (perFace > 1) {
    mesh->mNumFaces = static_cast<unsigned>(vertices.size() / perFace);
    mesh->mFaces = new aiFace[mesh->mNumFaces];
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      mesh->mFaces[f].mNumIndices = perFace;
      mesh->mFaces[f].mIndices = new unsigned[perFace];
      for (unsigned k = 0; k < perFace; ++k) mesh->mFaces[f].mIndices[k] = perFace * f + k;
    }
  }
  return addNodeOf(name, {mesh});
}

aiNode* Builder::addLines(const std::string& name, const std::vector<Eigen::Vector3d>& points,
                          unsigned material) {
  std::vector<aiVector3D> vertices;
  for (const Eigen::Vector3d& p : points) vertices.push_back(point(p));
  return addPrimitives(name, std::move(vertices), 2, aiPrimitiveType_LINE, material);
}

aiNode* Builder::addPoints(const std::string& name, const Vertices& points, unsigned material) {
  std::vector<aiVector3D> vertices;
  for (Eigen::Index v = 0; v < points.rows(); ++v)
    vertices.push_back(point(points.row(v).transpose()));
  return addPrimitives(name, std::move(vertices), 1, aiPrimitiveType_POINT, material);
}

void addSensedPoints(Builder& builder, const Scene& scene) {
  for (const Obstacle& o : scene.obstacles) {
    if (o.type != Obstacle::Type::kPoints || o.cloud == nullptr || o.cloud->points.rows() == 0)
      continue;
    Vertices world = o.cloud->points;
    for (Eigen::Index v = 0; v < world.rows(); ++v)
      world.row(v) = (o.pose * Eigen::Vector3d(world.row(v))).transpose();
    builder.addPoints(o.name + ".points", world, kPoints);
  }
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
