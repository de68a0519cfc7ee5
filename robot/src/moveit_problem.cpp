#include "robot/moveit_problem.h"

#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>

#include <cmath>
#include <map>
#include <optional>

#include "hfts_db/distance_grid.h"
#include "hfts_db/triangle_mesh.h"

namespace hfts::robot {

namespace {

/// One YAML file and checked access to its keys: errors name the file and
/// the key's path ("world.collision_objects[2].primitives[0].dimensions").
class YamlFile {
 public:
  explicit YamlFile(const std::filesystem::path& path) : source_(path.string()) {
    try {
      root_ = YAML::LoadFile(path.string());
    } catch (const YAML::BadFile&) {
      throw SceneError(source_, "", "cannot read the file");
    } catch (const YAML::Exception& e) {
      throw SceneError(source_, "", std::string("not valid YAML: ") + e.what());
    }
    if (!root_.IsMap()) throw SceneError(source_, "", "must be a YAML map");
  }

  const YAML::Node& root() const { return root_; }
  const std::string& source() const { return source_; }

  [[noreturn]] void fail(const std::string& field, const std::string& problem) const {
    throw SceneError(source_, field, problem);
  }

  /// The member `key` of the map `node` at `path`; nullopt when absent.
  static std::optional<YAML::Node> find(const YAML::Node& node, const std::string& key) {
    if (!node.IsMap() || !node[key]) return std::nullopt;
    return node[key];
  }

  YAML::Node at(const YAML::Node& node, const std::string& key, const std::string& path) const {
    std::optional<YAML::Node> n = find(node, key);
    if (!n) fail(join(path, key), "is required");
    return *n;
  }

  double number(const YAML::Node& node, const std::string& path) const {
    try {
      const double v = node.as<double>();
      if (std::isfinite(v)) return v;
    } catch (const YAML::Exception&) {
    }
    fail(path, "must be a finite number");
  }

  std::string text(const YAML::Node& node, const std::string& path) const {
    if (!node.IsScalar()) fail(path, "must be a string");
    return node.as<std::string>();
  }

  /// A sequence of exactly `n` numbers (n < 0: any length).
  std::vector<double> numbers(const YAML::Node& node, const std::string& path, int n) const {
    if (!node.IsSequence() || (n >= 0 && node.size() != static_cast<std::size_t>(n)))
      fail(path, n >= 0 ? "must be a list of " + std::to_string(n) + " numbers"
                        : std::string("must be a list of numbers"));
    std::vector<double> out;
    for (std::size_t i = 0; i < node.size(); ++i)
      out.push_back(number(node[i], path + "[" + std::to_string(i) + "]"));
    return out;
  }

  /// {position: [x,y,z], orientation: [x,y,z,w]} (geometry_msgs/Pose), or
  /// with `translation` / `rotation` (geometry_msgs/Transform).
  Eigen::Isometry3d pose(const YAML::Node& node, const std::string& path,
                         const char* position = "position",
                         const char* orientation = "orientation") const {
    const std::vector<double> p = numbers(at(node, position, path), join(path, position), 3);
    const std::vector<double> q = numbers(at(node, orientation, path), join(path, orientation), 4);
    const Eigen::Quaterniond rotation(q[3], q[0], q[1], q[2]);
    if (!(rotation.norm() > 1e-9)) fail(join(path, orientation), "has zero norm");
    Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
    out.linear() = rotation.normalized().toRotationMatrix();
    out.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
    return out;
  }

  static std::string join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }

 private:
  std::string source_;
  YAML::Node root_;
};

std::string indexed(const std::string& path, std::size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

/// One primitive (shape_msgs/SolidPrimitive) as an obstacle.
Obstacle primitive(const YamlFile& f, const YAML::Node& node, const std::string& path) {
  const std::string type = f.text(f.at(node, "type", path), YamlFile::join(path, "type"));
  const std::string dims = YamlFile::join(path, "dimensions");
  const YAML::Node dimensions = f.at(node, "dimensions", path);
  Obstacle o;
  if (type == "box" || type == "1") {
    const std::vector<double> d = f.numbers(dimensions, dims, 3);
    o.type = Obstacle::Type::kBox;
    o.size = Eigen::Vector3d(d[0], d[1], d[2]);
  } else if (type == "cylinder" || type == "3") {
    const std::vector<double> d = f.numbers(dimensions, dims, 2);  // height, radius
    o.type = Obstacle::Type::kCylinder;
    o.size = Eigen::Vector3d(d[1], d[0], 0.0);
  } else if (type == "sphere" || type == "2") {
    const std::vector<double> d = f.numbers(dimensions, dims, 1);
    o.type = Obstacle::Type::kSphere;
    o.size = Eigen::Vector3d(d[0], 0.0, 0.0);
  } else {
    f.fail(YamlFile::join(path, "type"),
           "'" + type + "' is not supported (box, cylinder or sphere)");
  }
  const int used = o.type == Obstacle::Type::kBox ? 3 : o.type == Obstacle::Type::kCylinder ? 2 : 1;
  if (!(o.size.head(used).array() > 0.0).all()) f.fail(dims, "must be positive");
  return o;
}

/// One inline mesh (shape_msgs/Mesh: `vertices` {x, y, z}, `triangles`
/// {vertex_indices}) in metres.
TriangleMesh mesh(const YamlFile& f, const YAML::Node& node, const std::string& path) {
  const YAML::Node vertices = f.at(node, "vertices", path);
  const YAML::Node triangles = f.at(node, "triangles", path);
  if (!vertices.IsSequence() || vertices.size() < 3)
    f.fail(YamlFile::join(path, "vertices"), "must be a list of at least 3 points");
  if (!triangles.IsSequence() || triangles.size() == 0)
    f.fail(YamlFile::join(path, "triangles"), "must be a non-empty list");
  TriangleMesh out;
  out.vertices.resize(static_cast<Eigen::Index>(vertices.size()), 3);
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const std::string at = indexed(YamlFile::join(path, "vertices"), i);
    const char* axes[] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a)
      out.vertices(static_cast<Eigen::Index>(i), a) =
          f.number(f.at(vertices[i], axes[a], at), YamlFile::join(at, axes[a]));
  }
  out.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const std::string at = indexed(YamlFile::join(path, "triangles"), t);
    const std::vector<double> v = f.numbers(f.at(triangles[t], "vertex_indices", at),
                                            YamlFile::join(at, "vertex_indices"), 3);
    for (int k = 0; k < 3; ++k) {
      if (!(v[k] >= 0.0 && v[k] < static_cast<double>(vertices.size()) && v[k] == std::floor(v[k])))
        f.fail(YamlFile::join(at, "vertex_indices"),
               "must be indices of the " + std::to_string(vertices.size()) + " vertices");
      out.triangles(static_cast<Eigen::Index>(t), k) = static_cast<std::uint32_t>(v[k]);
    }
  }
  return out;
}

/// The object's meshes as obstacles ("<id>/mesh<k>"), each with its
/// distance grid (signed when the mesh is closed).
void addMeshes(const YamlFile& f, const YAML::Node& object, const std::string& path,
               const std::string& id, const Eigen::Isometry3d& frame, Scene& scene) {
  const std::optional<YAML::Node> meshes = YamlFile::find(object, "meshes");
  if (!meshes || !meshes->IsSequence() || meshes->size() == 0) return;
  const YAML::Node poses = f.at(object, "mesh_poses", path);
  if (!poses.IsSequence() || poses.size() != meshes->size())
    f.fail(YamlFile::join(path, "mesh_poses"), "needs one pose per mesh");
  for (std::size_t k = 0; k < meshes->size(); ++k) {
    Obstacle o;
    o.type = Obstacle::Type::kMesh;
    o.name = id + "/mesh" + std::to_string(k);
    o.mesh = mesh(f, (*meshes)[k], indexed(YamlFile::join(path, "meshes"), k));
    o.pose = frame * f.pose(poses[k], indexed(YamlFile::join(path, "mesh_poses"), k));
    o.distance_grid = std::make_shared<const db::DistanceGrid>(
        db::buildDistanceGrid(o.mesh, analyzeTopology(o.mesh).closed()));
    scene.obstacles.push_back(std::move(o));
  }
}

void addCollisionObjects(const YamlFile& f, Scene& scene) {
  const std::optional<YAML::Node> world = YamlFile::find(f.root(), "world");
  if (!world) return;
  const std::optional<YAML::Node> objects = YamlFile::find(*world, "collision_objects");
  if (!objects) return;
  if (!objects->IsSequence()) f.fail("world.collision_objects", "must be a list");
  for (std::size_t i = 0; i < objects->size(); ++i) {
    const YAML::Node object = (*objects)[i];
    const std::string path = indexed("world.collision_objects", i);
    const std::string id = f.text(f.at(object, "id", path), YamlFile::join(path, "id"));
    if (const auto n = YamlFile::find(object, "planes"); n && n->IsSequence() && n->size() > 0)
      f.fail(YamlFile::join(path, "planes"),
             "object '" + id + "': planes are not supported (boxes, cylinders, spheres, meshes)");
    // Newer scenes give the object's pose and its primitives' poses in it.
    const Eigen::Isometry3d frame = YamlFile::find(object, "pose")
                                        ? f.pose(object["pose"], YamlFile::join(path, "pose"))
                                        : Eigen::Isometry3d::Identity();
    addMeshes(f, object, path, id, frame, scene);
    const std::optional<YAML::Node> primitives = YamlFile::find(object, "primitives");
    if (!primitives) continue;
    const YAML::Node poses = f.at(object, "primitive_poses", path);
    if (!primitives->IsSequence() || !poses.IsSequence() || poses.size() != primitives->size())
      f.fail(YamlFile::join(path, "primitive_poses"), "needs one pose per primitive");
    for (std::size_t k = 0; k < primitives->size(); ++k) {
      Obstacle o = primitive(f, (*primitives)[k], indexed(YamlFile::join(path, "primitives"), k));
      o.name = primitives->size() == 1 ? id : id + "/" + std::to_string(k);
      o.pose = frame * f.pose(poses[k], indexed(YamlFile::join(path, "primitive_poses"), k));
      scene.obstacles.push_back(std::move(o));
    }
  }
}

/// joint_state {name: [...], position: [...]} as a map, or empty.
std::map<std::string, double> jointState(const YamlFile& f, const YAML::Node& state,
                                         const std::string& path) {
  std::map<std::string, double> out;
  const std::optional<YAML::Node> joints = YamlFile::find(state, "joint_state");
  if (!joints) return out;
  const std::string p = YamlFile::join(path, "joint_state");
  const YAML::Node names = f.at(*joints, "name", p);
  const std::vector<double> positions =
      f.numbers(f.at(*joints, "position", p), YamlFile::join(p, "position"),
                names.IsSequence() ? int(names.size()) : -1);
  for (std::size_t i = 0; i < positions.size(); ++i)
    out[f.text(names[i], indexed(YamlFile::join(p, "name"), i))] = positions[i];
  return out;
}

/// The robot's base in the world: the virtual joint's transform, when the
/// robot state gives one.
Eigen::Isometry3d robotBase(const YamlFile& f) {
  const auto state = YamlFile::find(f.root(), "robot_state");
  const auto multi = state ? YamlFile::find(*state, "multi_dof_joint_state") : std::nullopt;
  const auto transforms = multi ? YamlFile::find(*multi, "transforms") : std::nullopt;
  if (!transforms || !transforms->IsSequence() || transforms->size() == 0)
    return Eigen::Isometry3d::Identity();
  return f.pose((*transforms)[0], "robot_state.multi_dof_joint_state.transforms[0]", "translation",
                "rotation");
}

void checkAllowedCollisions(const YamlFile& f, const RobotModel& robot, MoveItProblem& out) {
  const auto acm = YamlFile::find(f.root(), "allowed_collision_matrix");
  if (!acm) return;
  const YAML::Node names = f.at(*acm, "entry_names", "allowed_collision_matrix");
  const YAML::Node values = f.at(*acm, "entry_values", "allowed_collision_matrix");
  if (!names.IsSequence() || !values.IsSequence() || values.size() != names.size())
    f.fail("allowed_collision_matrix.entry_values", "needs one row per entry name");
  std::vector<int> links;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string name = f.text(names[i], indexed("allowed_collision_matrix.entry_names", i));
    int link = -1;
    for (std::size_t l = 0; l < robot.links().size(); ++l)
      if (robot.links()[l].name == name) link = static_cast<int>(l);
    links.push_back(link);
  }
  for (std::size_t i = 0; i < names.size(); ++i) {
    const YAML::Node row = values[i];
    if (!row.IsSequence() || row.size() != names.size())
      f.fail(indexed("allowed_collision_matrix.entry_values", i), "needs one value per entry");
    for (std::size_t j = i + 1; j < names.size(); ++j) {
      bool allowed = false;
      try {
        allowed = row[j].as<bool>();
      } catch (const YAML::Exception&) {
        f.fail(indexed(indexed("allowed_collision_matrix.entry_values", i), j),
               "must be true or false");
      }
      if (allowed && links[i] >= 0 && links[j] >= 0 &&
          robot.links()[static_cast<std::size_t>(links[i])].shapes.size() > 0 &&
          robot.links()[static_cast<std::size_t>(links[j])].shapes.size() > 0 &&
          !robot.isCollisionDisabled(links[i], links[j]))
        out.stricter_pairs.emplace_back(names[i].as<std::string>(), names[j].as<std::string>());
    }
  }
}

/// The robot's DoFs from `values` (a DoF missing there from `fallback`),
/// checked against the joint limits.
Eigen::VectorXd configuration(const YamlFile& f, const RobotModel& robot,
                              const std::map<std::string, double>& values,
                              const std::map<std::string, double>& fallback,
                              const std::string& field) {
  Eigen::VectorXd q(robot.numDofs());
  for (int d = 0; d < robot.numDofs(); ++d) {
    const std::string& name = robot.dofNames()[static_cast<std::size_t>(d)];
    if (const auto it = values.find(name); it != values.end())
      q(d) = it->second;
    else if (const auto at = fallback.find(name); at != fallback.end())
      q(d) = at->second;
    else
      f.fail(field, "gives no value for joint '" + name + "'");
  }
  std::string why;
  if (!robot.withinLimits(q, 1e-6, &why)) f.fail(field, why);
  // Within the tolerance but outside by rounding: onto the limit.
  q = q.cwiseMax(robot.lowerLimits()).cwiseMin(robot.upperLimits());
  return q;
}

}  // namespace

MoveItProblem loadMoveItProblem(const RobotModel& robot, const std::filesystem::path& sceneYaml,
                                const std::filesystem::path& requestYaml) {
  const YamlFile scene(sceneYaml);
  const YamlFile request(requestYaml);
  MoveItProblem out;
  out.scene.name = sceneYaml.stem().string();
  out.scene.robot_base = robotBase(scene);
  addCollisionObjects(scene, out.scene);
  checkAllowedCollisions(scene, robot, out);

  const auto sceneState = YamlFile::find(scene.root(), "robot_state");
  const std::map<std::string, double> sceneJoints =
      sceneState ? jointState(scene, *sceneState, "robot_state") : std::map<std::string, double>{};
  const auto startState = YamlFile::find(request.root(), "start_state");
  const std::map<std::string, double> startJoints =
      startState ? jointState(request, *startState, "start_state")
                 : std::map<std::string, double>{};
  out.start = configuration(request, robot, startJoints, sceneJoints, "start_state");

  const YAML::Node goals = request.at(request.root(), "goal_constraints", "");
  if (!goals.IsSequence() || goals.size() == 0)
    request.fail("goal_constraints", "must be a non-empty list");
  const YAML::Node joints = request.at(goals[0], "joint_constraints", "goal_constraints[0]");
  if (!joints.IsSequence()) request.fail("goal_constraints[0].joint_constraints", "must be a list");
  std::map<std::string, double> goal;
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const std::string path = indexed("goal_constraints[0].joint_constraints", i);
    const std::string name =
        request.text(request.at(joints[i], "joint_name", path), YamlFile::join(path, "joint_name"));
    if (!goal.emplace(name, request.number(request.at(joints[i], "position", path),
                                           YamlFile::join(path, "position")))
             .second)
      request.fail(path, "joint '" + name + "' is constrained twice");
  }
  out.goal = configuration(request, robot, goal, {}, "goal_constraints[0].joint_constraints");
  return out;
}

}  // namespace hfts::robot
