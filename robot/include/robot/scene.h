#pragma once
// Planning scenes: where the robot stands, the obstacles around it, the
// target object and a start configuration. File format: docs/scenes.md.

#include <Eigen/Geometry>

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "hfts_db/distance_grid.h"
#include "hfts_db/triangle_mesh.h"
#include "robot/point_cloud.h"
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
  /// kPoints: what a sensor saw (a point cloud or a depth image), as
  /// occupied voxels (point_cloud.h).
  enum class Type { kBox, kCylinder, kSphere, kMesh, kPoints };
  std::string name;
  Type type = Type::kBox;
  /// Box: edge lengths. Cylinder: radius, length (along local z), 0.
  /// Sphere: radius, 0, 0. Mesh: unused.
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  /// kMesh: loaded and scaled to metres. kPoints: the occupied voxels'
  /// boxes (VoxelCloud::mesh), for drawing and the highest point.
  TriangleMesh mesh;
  /// kMesh only: distances from `mesh` (mesh frame; signed when the mesh is
  /// closed), built with the default DistanceGridOptions when the scene is
  /// parsed. Shared, so copies of a scene do not copy it.
  std::shared_ptr<const db::DistanceGrid> distance_grid;
  /// kPoints only: the cloud's voxels, built when the scene is parsed.
  /// Shared, as the grid.
  std::shared_ptr<const VoxelCloud> cloud;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< in the world frame
};

static_assert(static_cast<int>(Obstacle::Type::kBox) ==
                      static_cast<int>(CollisionShape::Type::kBox) &&
                  static_cast<int>(Obstacle::Type::kCylinder) ==
                      static_cast<int>(CollisionShape::Type::kCylinder) &&
                  static_cast<int>(Obstacle::Type::kSphere) ==
                      static_cast<int>(CollisionShape::Type::kSphere),
              "obstacle and link primitive types must match");

/// Where a target stands: a pose, and optionally the obstacle it rests on.
struct Placement {
  std::string name;  ///< "target" for the scene's own; otherwise as the file names it
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< object frame in the world
  /// An obstacle of the scene, or empty. When set, the pose's z is not
  /// used as given: the object is lowered (or raised) until its lowest
  /// point lies on the obstacle's top (restingPose).
  std::string rest_on;
};

struct Scene {
  std::string name;
  std::string description;
  Eigen::Isometry3d robot_base = Eigen::Isometry3d::Identity();  ///< base link in the world
  std::vector<Obstacle> obstacles;
  std::string target_object;                                      ///< object database name
  Eigen::Isometry3d target_pose = Eigen::Isometry3d::Identity();  ///< object frame in the world
  std::string target_rest_on;  ///< obstacle the target rests on, or empty (Placement::rest_on)
  /// Other named places for the target (`placements` in the file), e.g.
  /// lying or near a wall; withPlacement() makes one the target's.
  std::vector<Placement> placements;
  /// The robot's start configuration (`start` as an array in the file),
  /// for any robot with that many DoF; the robot's home if absent.
  std::optional<Eigen::VectorXd> start;
  /// Starts per robot (`start` as an object in the file: {"<robot name>":
  /// [...]}), so that one scene serves several robots.
  std::map<std::string, Eigen::VectorXd> robot_starts;

  /// The start of the robot named `robot`: its entry of robot_starts, else
  /// `start` (nullopt: the robot's home).
  std::optional<Eigen::VectorXd> startFor(const std::string& robot) const;

  /// The obstacle named `name`, or nullptr.
  const Obstacle* obstacle(const std::string& name) const;
  /// The scene with placement `name` as the target's ("target": the
  /// scene's own). Throws SceneError (field "placements") for an unknown name.
  Scene withPlacement(const std::string& name) const;
};

/// The highest point of an obstacle in the world (its top face when the
/// top is level, as for a table, a shelf board or a bin floor).
double topOf(const Obstacle& obstacle);

/// Gap between a resting object and its support (m): touching would count
/// as a collision of the target with an obstacle.
inline constexpr double kRestingClearance = 0.001;

/// `pose` moved along the world z axis until the lowest of `vertices`
/// (object frame, one per row) lies kRestingClearance above the top of
/// `support`.
Eigen::Isometry3d restingPose(const Eigen::Isometry3d& pose, const Vertices& vertices,
                              const Obstacle& support);

/// Where the target with these vertices stands in `scene`: target_pose,
/// resting on target_rest_on when that is set.
Eigen::Isometry3d targetPose(const Scene& scene, const Vertices& vertices);

/// Reads a scene file; mesh obstacles are loaded relative to its folder,
/// and each gets its distance grid (about 0.1 to 1 s per mesh on one
/// core, up to 1 MiB). Throws SceneError.
Scene loadScene(const std::filesystem::path& path);

/// Parses scene JSON text; `baseDir` resolves mesh paths, `what` names the
/// source in errors. Mesh obstacles get their distance grids as in
/// loadScene. Throws SceneError.
Scene parseScene(const std::string& json, const std::filesystem::path& baseDir,
                 const std::string& what);

/// Parses a JSON array of obstacles in the scene file format (a plan
/// request's `obstacles`) as parseScene parses a scene's: `baseDir`
/// resolves files, errors name the member ("obstacles[1].voxel") and names
/// must differ. Throws SceneError.
std::vector<Obstacle> parseObstacles(const std::string& json, const std::filesystem::path& baseDir,
                                     const std::string& what);

/// A depth_image obstacle of a scene file that has a mask: one camera's
/// view of the scene's target (the masked pixels) and of what is around it.
struct TargetView {
  std::string name;  ///< the obstacle's
  /// The camera's optical frame (x right, y down, z along the view) in the
  /// world: the obstacle's pose.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  DepthCamera camera;
  /// Depths in metres; 0 where the camera read nothing in [min_depth,
  /// max_depth].
  DepthImage image;
  std::vector<std::uint8_t> mask;  ///< 1 where the pixel sees the target
};

/// The target views of a scene file (its depth_image obstacles with a
/// mask), read as the obstacles are. Throws SceneError naming the member,
/// or when the scene has none.
std::vector<TargetView> loadTargetViews(const std::filesystem::path& path);

/// True for a name that is safe as a file stem: letters, digits, '_', '-',
/// '.', not starting with '.', at most 128 characters (no path characters).
bool isSafeName(const std::string& name);

}  // namespace hfts::robot
