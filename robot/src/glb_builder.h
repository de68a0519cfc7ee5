#pragma once
// What the scene and plan exports share: triangle parts with one of a few
// materials, one named node per part, lines and points, written with
// assimp's glTF 2 exporter (robot/scene_export.h, robot/plan_export.h).

#include <assimp/scene.h>

#include <filesystem>
#include <string>
#include <vector>

#include "hfts_db/object_database.h"
#include "robot/robot_model.h"
#include "robot/scene.h"

namespace hfts::robot::glb {

enum Material : unsigned {
  kArm,
  kHand,
  kFingertip,
  kObstacle,
  kTarget,
  kMarker,
  kPath,
  kPoints,  ///< what a sensor saw: a cloud's points
  kMaterials
};

struct Part {
  TriangleMesh mesh;
  unsigned material = 0;
  std::string name;
};

TriangleMesh transformed(TriangleMesh mesh, const Eigen::Isometry3d& pose);

/// A link's or an obstacle's primitive: `type` a CollisionShape::Type or
/// Obstacle::Type value (they agree, see scene.h) other than kMesh.
TriangleMesh primitiveMesh(int type, const Eigen::Vector3d& size);

/// The material of link l: arm, hand or fingertip link.
unsigned linkMaterial(const RobotModel& model, std::size_t l);

/// The obstacles (world frame) and the target object at `targetPose`.
std::vector<Part> environmentParts(const Scene& scene, const db::ObjectGeometry* target,
                                   const Eigen::Isometry3d& targetPose);

class Builder;

/// For each sensed obstacle (Obstacle::Type::kPoints) of `scene`, a node
/// "<obstacle name>.points" of its cloud's points in the world frame, beside
/// the voxels environmentParts draws: the voxels are what the planner
/// avoids, the points what the sensor saw.
void addSensedPoints(Builder& builder, const Scene& scene);

/// An assimp scene under construction: the materials, a root node turned
/// from the world's z up to glTF's y up, and the parts added to it.
class Builder {
 public:
  Builder();
  ~Builder();
  Builder(const Builder&) = delete;
  Builder& operator=(const Builder&) = delete;
  /// A node named `name` under the root holding `parts` (their own frames);
  /// returns it, so a caller can animate or place it.
  aiNode* addNode(const std::string& name, const std::vector<Part>& parts);
  /// A node of line segments (pairs of points, world frame).
  aiNode* addLines(const std::string& name, const std::vector<Eigen::Vector3d>& points,
                   unsigned material);
  /// A node of points (one per row, world frame): glTF's mode POINTS,
  /// without indices.
  aiNode* addPoints(const std::string& name, const Vertices& points, unsigned material);
  aiScene& scene() { return scene_; }
  /// The binary glTF; throws std::runtime_error naming `what` if assimp fails.
  std::string glb(const std::string& what);

 private:
  aiScene scene_;
  std::vector<aiMesh*> meshes_;
  std::vector<aiNode*> nodes_;
  unsigned addMesh(aiMesh* mesh);
  /// A node under the root holding `meshes` (added to the scene).
  aiNode* addNodeOf(const std::string& name, const std::vector<aiMesh*>& meshes);
  /// A node of one mesh of `vertices` taken `perFace` at a time as
  /// primitives of `type` (lines, points).
  aiNode* addPrimitives(const std::string& name, std::vector<aiVector3D> vertices, unsigned perFace,
                        aiPrimitiveType type, unsigned material);
};

}  // namespace hfts::robot::glb
