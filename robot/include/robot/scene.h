#pragma once
// Planning scenes: where the robot stands, the obstacles around it, the
// target object and a start configuration. File format: docs/scenes.md.

#include <Eigen/Geometry>

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "hfts_db/triangle_mesh.h"
#include "robot/robot_model.h"

namespace hfts::robot {

/// A scene that cannot be read. `field` is the path of the bad member in
/// the scene's JSON ("obstacles[2].size", "target.pose.orientation"; empty
/// for the file or text as a whole); what() is
/// "<source>: <field>: <problem>", e.g. "scene 'shelf.json': obstacles[2].size:
/// must be positive".
class SceneError : public std::runtime_error {
 public:
  SceneError(const std::string& source, std::string field, std::string problem);
  const std::string& field() const { return field_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string field_;
  std::string problem_;
};

struct Obstacle {
  /// The first three match CollisionShape::Type value for value, so code
  /// that handles primitives can treat robot links and obstacles alike.
  enum class Type { kBox, kCylinder, kSphere, kMesh };
  std::string name;
  Type type = Type::kBox;
  /// Box: edge lengths. Cylinder: radius, length (along local z), 0.
  /// Sphere: radius, 0, 0. Mesh: unused.
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  TriangleMesh mesh;  ///< kMesh only: loaded and scaled to metres
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< in the world frame
};

static_assert(static_cast<int>(Obstacle::Type::kBox) ==
                      static_cast<int>(CollisionShape::Type::kBox) &&
                  static_cast<int>(Obstacle::Type::kCylinder) ==
                      static_cast<int>(CollisionShape::Type::kCylinder) &&
                  static_cast<int>(Obstacle::Type::kSphere) ==
                      static_cast<int>(CollisionShape::Type::kSphere),
              "obstacle and link primitive types must match");

struct Scene {
  std::string name;
  std::string description;
  Eigen::Isometry3d robot_base = Eigen::Isometry3d::Identity();  ///< base link in the world
  std::vector<Obstacle> obstacles;
  std::string target_object;                                      ///< object database name
  Eigen::Isometry3d target_pose = Eigen::Isometry3d::Identity();  ///< object frame in the world
  std::optional<Eigen::VectorXd> start;  ///< robot configuration; the robot's home if absent
};

/// Reads a scene file; mesh obstacles are loaded relative to its folder.
/// Throws SceneError.
Scene loadScene(const std::filesystem::path& path);

/// Parses scene JSON text; `baseDir` resolves mesh paths, `what` names the
/// source in errors. Throws SceneError.
Scene parseScene(const std::string& json, const std::filesystem::path& baseDir,
                 const std::string& what);

/// True for a name that is safe as a file stem: letters, digits, '_', '-',
/// '.', not starting with '.', at most 128 characters (no path characters).
bool isSafeName(const std::string& name);

}  // namespace hfts::robot
