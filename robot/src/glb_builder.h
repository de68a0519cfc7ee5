#pragma once
// What the scene and plan exports share: triangle parts with one of a few
// materials, one named node per part, written with assimp's glTF 2
// exporter (robot/scene_export.h, robot/plan_export.h).

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
  aiScene& scene() { return scene_; }
  /// The binary glTF; throws std::runtime_error naming `what` if assimp fails.
  std::string glb(const std::string& what);

 private:
  aiScene scene_;
  std::vector<aiMesh*> meshes_;
  std::vector<aiNode*> nodes_;
  unsigned addMesh(aiMesh* mesh);
};

}  // namespace hfts::robot::glb
