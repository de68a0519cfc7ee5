// Robots, scenes, planning worlds, IK and collision checks.

#include <mutex>

#include "batch.h"
#include "bindings.h"
#include "core/invalid_argument.h"
#include "grasp/hand_map_builder.h"
#include "planner/planning_world.h"
#include "robot/collision_checker.h"
#include "robot/kinematics.h"
#include "robot/scene.h"

namespace hfts::python {
namespace {

using planner::PlanningWorld;
using robot::RobotModel;
using robot::Scene;

/// The robot's configuration `q` checked: numDofs() finite values within
/// the joint limits.
void checkConfiguration(const RobotModel& robot, const Eigen::VectorXd& q, const char* field) {
  std::string why;
  if (!robot.withinLimits(q, 1e-9, &why)) throw InvalidArgument(field, why);
}

/// One robot in one scene for collision checks: a checker (one thread's
/// working state) behind a lock, so that Python threads may share it.
class SceneChecker {
 public:
  SceneChecker(std::shared_ptr<const PlanningWorld> world, Scene scene, const std::string& object,
               const std::optional<DoubleArray>& objectPose)
      : world_(std::move(world)), scene_(std::move(scene)) {
    if (!object.empty()) scene_.target_object = object;
    const db::ObjectDatabase* target = nullptr;
    if (!scene_.target_object.empty()) {
      target = world_->object(scene_.target_object);
      if (target == nullptr)
        throw InvalidArgument("object", "no database named '" + scene_.target_object +
                                            "' in the world (World.object_names)");
      scene_.target_pose = objectPose ? isometryOf(*objectPose, "object_pose")
                                      : robot::targetPose(scene_, target->geometry.mesh_vertices);
    }
    checker_ = std::make_unique<robot::CollisionChecker>(
        world_->collisionModel(), scene_, target ? &target->geometry : nullptr,
        target ? world_->collisionMesh(scene_.target_object) : nullptr,
        target ? world_->surface(scene_.target_object) : nullptr);
  }

  bool inCollision(const Eigen::VectorXd& q, const robot::CollisionRequest& request) {
    checkConfiguration(world_->robot(), q, "configuration");
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(mutex_);
    return checker_->inCollision(q, request);
  }

  py::array_t<bool> inCollisionBatch(const DoubleArray& configurations,
                                     const robot::CollisionRequest& request) {
    const int dofs = world_->robot().numDofs();
    checkShape(configurations, "configurations", {-1, dofs});
    const auto count = static_cast<std::size_t>(configurations.shape(0));
    py::array_t<bool> out(static_cast<py::ssize_t>(count));
    const double* in = configurations.data();
    bool* colliding = out.mutable_data();
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(mutex_);
    collisionBatch(*checker_, in, count, dofs, request, colliding);
    return out;
  }

  double clearance(const Eigen::VectorXd& q) {
    checkConfiguration(world_->robot(), q, "configuration");
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(mutex_);
    return checker_->clearance(q);
  }

  const Scene& scene() const { return scene_; }

 private:
  std::shared_ptr<const PlanningWorld> world_;
  Scene scene_;
  std::unique_ptr<robot::CollisionChecker> checker_;
  std::mutex mutex_;
};

robot::CollisionRequest collisionRequest(const std::string& rule, bool target, bool self,
                                         bool obstacles) {
  if (rule != "strict" && rule != "grasp")
    throw InvalidArgument("rule", "must be \"strict\" or \"grasp\", got \"" + rule + "\"");
  robot::CollisionRequest request;
  request.rule = rule == "grasp" ? robot::CollisionRequest::Rule::kGraspRule
                                 : robot::CollisionRequest::Rule::kStrict;
  request.target = target;
  request.self = self;
  request.obstacles = obstacles;
  return request;
}

/// The IK of one pose: solutions as rows.
Eigen::MatrixXd solutionsOf(const PlanningWorld& world, const DoubleArray& pose,
                            const std::string& link, const py::object& seed) {
  if (link != "palm" && link != "flange")
    throw InvalidArgument("link", "must be \"palm\" or \"flange\", got \"" + link + "\"");
  isometryOf(pose, "pose");  // checked here to name the field; solved as given
  const std::uint64_t first = seedOf(seed);
  IkSolutions found;
  {
    py::gil_scoped_release release;
    found = armIkBatch(world.ik(), pose.data(), 1, link == "palm", first);
  }
  const auto arm = static_cast<Eigen::Index>(world.robot().numArmDofs());
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      found.configurations.data(), static_cast<Eigen::Index>(found.pose_index.size()), arm);
}

py::tuple ikBatch(const PlanningWorld& world, const DoubleArray& poses, const std::string& link,
                  const py::object& seed) {
  if (link != "palm" && link != "flange")
    throw InvalidArgument("link", "must be \"palm\" or \"flange\", got \"" + link + "\"");
  checkShape(poses, "poses", {-1, 4, 4});
  const std::uint64_t first = seedOf(seed);
  const double* data = poses.data();
  const auto count = static_cast<std::size_t>(poses.shape(0));
  IkSolutions found;
  {
    py::gil_scoped_release release;
    found = armIkBatch(world.ik(), data, count, link == "palm", first);
  }
  const auto arm = static_cast<py::ssize_t>(world.robot().numArmDofs());
  const auto n = static_cast<py::ssize_t>(found.pose_index.size());
  py::array_t<double> solutions({n, arm});
  std::copy(found.configurations.begin(), found.configurations.end(), solutions.mutable_data());
  py::array_t<std::int64_t> index(n);
  std::copy(found.pose_index.begin(), found.pose_index.end(), index.mutable_data());
  return py::make_tuple(solutions, index);
}

/// Every link's pose (world frame with `base`) at q, as an (L, 4, 4) array.
py::array_t<double> linkPoses(const RobotModel& robot, const Eigen::VectorXd& q,
                              const std::optional<DoubleArray>& base) {
  checkConfiguration(robot, q, "configuration");
  const Eigen::Isometry3d b = base ? isometryOf(*base, "base") : Eigen::Isometry3d::Identity();
  const robot::LinkPoses poses = robot::forwardKinematics(robot, q);
  py::array_t<double> out({static_cast<py::ssize_t>(poses.size()), py::ssize_t{4}, py::ssize_t{4}});
  double* data = out.mutable_data();
  for (const Eigen::Isometry3d& pose : poses) {
    Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> matrix(data);
    matrix = (b * pose).matrix();
    data += 16;
  }
  return out;
}

std::vector<std::string> linkNames(const RobotModel& robot) {
  std::vector<std::string> names;
  for (const robot::Link& link : robot.links()) names.push_back(link.name);
  return names;
}

}  // namespace

void bindRobot(py::module_& m) {
  py::class_<RobotModel>(m, "Robot",
                         "A robot: its URDF kinematics and the config of docs/robots.md (joint "
                         "order: the arm's DoF, then the hand's).")
      .def_static(
          "load", [](const std::filesystem::path& config) { return RobotModel::load(config); },
          py::arg("config"), "Loads a robot config (JSON) and the URDF it names.")
      .def_static(
          "from_strings",
          [](const std::string& urdf, const std::string& config, const std::string& srdf) {
            return RobotModel::fromStrings(urdf, config, "robot from Python", srdf);
          },
          py::arg("urdf"), py::arg("config"), py::arg("srdf") = "",
          "A robot from URDF text and config JSON text (and optionally SRDF text for the "
          "collision pairs it disables).")
      .def_property_readonly("name", &RobotModel::name)
      .def_property_readonly("num_dofs", &RobotModel::numDofs)
      .def_property_readonly("num_arm_dofs", &RobotModel::numArmDofs)
      .def_property_readonly("num_hand_dofs", &RobotModel::numHandDofs)
      .def_property_readonly("dof_names", &RobotModel::dofNames,
                             "Every DoF's name: the arm's joints from the base, then the hand's.")
      .def_property_readonly("lower_limits", &RobotModel::lowerLimits)
      .def_property_readonly("upper_limits", &RobotModel::upperLimits)
      .def_property_readonly("max_velocities", &RobotModel::maxVelocities)
      .def_property_readonly("max_accelerations", &RobotModel::maxAccelerations,
                             "From the config (rad/s^2, m/s^2); empty when it gives none (then "
                             "no trajectories).")
      .def_property_readonly("home", &RobotModel::home)
      .def_property_readonly("has_hand", &RobotModel::hasHand)
      .def_property_readonly("link_names", &linkNames)
      .def_property_readonly("palm_link",
                             [](const RobotModel& r) {
                               return r.links()[static_cast<std::size_t>(r.palmLink())].name;
                             })
      .def_property_readonly("flange_link",
                             [](const RobotModel& r) {
                               return r.links()[static_cast<std::size_t>(r.flangeLink())].name;
                             })
      .def("link_poses", &linkPoses, py::arg("configuration"), py::arg("base") = py::none(),
           "Every link's pose at a configuration, as an (L, 4, 4) array in link_names order "
           "(the robot's base at `base`).")
      .def("__repr__", [](const RobotModel& r) {
        return "<hfts.Robot '" + r.name() + "' with " + std::to_string(r.numDofs()) + " DoF>";
      });

  py::class_<Scene>(m, "Scene",
                    "A scene (docs/scenes.md): obstacles, the robot's base, the target object "
                    "and where it stands, the start.")
      .def_static(
          "load", [](const std::filesystem::path& path) { return robot::loadScene(path); },
          py::arg("path"), "Reads a scene file (mesh obstacles relative to its folder).")
      .def_static(
          "from_json",
          [](const std::string& text, const std::filesystem::path& base_dir) {
            return robot::parseScene(text, base_dir, "scene from Python");
          },
          py::arg("text"), py::arg("base_dir") = std::filesystem::path("."),
          "A scene from JSON text (mesh paths relative to base_dir).")
      .def_readonly("name", &Scene::name)
      .def_readonly("description", &Scene::description)
      .def_readonly("target_object", &Scene::target_object)
      .def_property_readonly("robot_base", [](const Scene& s) { return s.robot_base.matrix(); })
      .def_property_readonly("target_pose", [](const Scene& s) { return s.target_pose.matrix(); })
      .def_property_readonly("obstacle_names",
                             [](const Scene& s) {
                               std::vector<std::string> names;
                               for (const auto& o : s.obstacles) names.push_back(o.name);
                               return names;
                             })
      .def_property_readonly("placement_names",
                             [](const Scene& s) {
                               std::vector<std::string> names{"target"};
                               for (const auto& p : s.placements) names.push_back(p.name);
                               return names;
                             })
      .def("start_for", &Scene::startFor, py::arg("robot_name"),
           "The scene's start for the robot of that name (None: the robot's home).")
      .def("with_placement", &Scene::withPlacement, py::arg("name"),
           "The scene with one of its placements as the target's.")
      .def("__repr__", [](const Scene& s) { return "<hfts.Scene '" + s.name + "'>"; });

  py::class_<db::HandMap>(m, "HandMap",
                          "A hand reachability map (docs/grasp_planning.md): fingertip "
                          "positions and pad normals of sampled hand postures.")
      .def_static(
          "load", [](const std::filesystem::path& path) { return db::loadHandMap(path); },
          py::arg("path"), "Reads a hand map file (<robot>_hand_map.h5, hfts-preprocess --hand).")
      .def_static(
          "build",
          [](const RobotModel& robot) {
            py::gil_scoped_release release;
            return grasp::buildHandMap(robot, grasp::handMapOptions(robot));
          },
          py::arg("robot"),
          "Builds the robot's hand map with its default options (as hfts-preprocess --hand).")
      .def(
          "save",
          [](const db::HandMap& map, const std::filesystem::path& path) {
            db::saveHandMap(map, path);
          },
          py::arg("path"), "Writes the map (HDF5, atomically).")
      .def_readonly("robot_name", &db::HandMap::robot_name)
      .def_property_readonly("num_samples", &db::HandMap::numSamples)
      .def_readonly("configurations", &db::HandMap::configurations,
                    "The sampled hand postures (N, hand DoF), a read-only view.")
      .def("__repr__", [](const db::HandMap& h) {
        return "<hfts.HandMap of '" + h.robot_name + "' with " + std::to_string(h.numSamples()) +
               " samples>";
      });

  py::class_<SceneChecker>(m, "CollisionChecker",
                           "Collision checks of a world's robot in one scene (World.checker). "
                           "Safe to share between threads (calls take turns).")
      .def(
          "in_collision",
          [](SceneChecker& c, const Eigen::VectorXd& q, const std::string& rule, bool target,
             bool self, bool obstacles) {
            return c.inCollision(q, collisionRequest(rule, target, self, obstacles));
          },
          py::arg("configuration"), py::arg("rule") = "strict", py::arg("target") = true,
          py::arg("self_collision") = true, py::arg("obstacles") = true,
          "Whether the robot at the configuration touches what counts: rule \"strict\" (any "
          "contact) or \"grasp\" (fingertips may touch the target, docs/collision.md).")
      .def(
          "in_collision_batch",
          [](SceneChecker& c, const DoubleArray& q, const std::string& rule, bool target, bool self,
             bool obstacles) {
            return c.inCollisionBatch(q, collisionRequest(rule, target, self, obstacles));
          },
          py::arg("configurations"), py::arg("rule") = "strict", py::arg("target") = true,
          py::arg("self_collision") = true, py::arg("obstacles") = true,
          "in_collision of each row of an (N, num_dofs) array, the sphere tier testing them a "
          "batch at a time: a bool array of N.")
      .def("clearance", &SceneChecker::clearance, py::arg("configuration"),
           "Smallest distance (m) between the robot and the scene (the target included); 0 "
           "in collision.")
      .def_property_readonly("scene", &SceneChecker::scene)
      .def("__repr__", [](const SceneChecker& c) {
        return "<hfts.CollisionChecker in '" + c.scene().name + "'" +
               (c.scene().target_object.empty() ? "" : " with '" + c.scene().target_object + "'") +
               ">";
      });

  py::class_<PlanningWorld, std::shared_ptr<PlanningWorld>>(
      m, "World",
      "What plans are made with: a robot, its hand map and object databases. Immutable; share "
      "it between threads.")
      .def_static(
          "load",
          [](const std::filesystem::path& robot_config, const std::filesystem::path& db_dir) {
            std::vector<std::string> skipped;
            std::shared_ptr<const PlanningWorld> world;
            {
              py::gil_scoped_release release;
              try {
                world = PlanningWorld::load(robot_config, db_dir, &skipped);
              } catch (const robot::ModelError&) {
                throw;
              } catch (const db::DatabaseError&) {
                throw;
              } catch (const std::runtime_error& e) {
                // A missing folder or hand map: the files a world is read from.
                throw db::DatabaseError(e.what());
              }
            }
            for (const std::string& s : skipped)
              if (PyErr_WarnEx(PyExc_RuntimeWarning, ("skipped a database: " + s).c_str(), 1) < 0)
                throw py::error_already_set();  // warnings are errors
            return std::const_pointer_cast<PlanningWorld>(world);
          },
          py::arg("robot_config"), py::arg("db_dir"),
          "Loads a robot config and, from db_dir, its hand map (<robot>_hand_map.h5) and every "
          "object database (a database that does not load is skipped with a warning).")
      .def(py::init([](const RobotModel& robot, const db::HandMap& hand_map,
                       const std::vector<db::ObjectDatabase>& objects) {
             std::map<std::string, db::ObjectDatabase> byName;
             for (const db::ObjectDatabase& o : objects) {
               if (!byName.emplace(o.name, o).second)
                 throw InvalidArgument("objects", "two databases are named '" + o.name + "'");
             }
             py::gil_scoped_release release;
             return std::make_shared<PlanningWorld>(robot, hand_map, std::move(byName));
           }),
           py::arg("robot"), py::arg("hand_map"), py::arg("objects"),
           "A world of a robot, its hand map and object databases (ObjectDatabase).")
      .def_property_readonly("robot", &PlanningWorld::robot,
                             py::return_value_policy::reference_internal)
      .def_property_readonly("object_names", &PlanningWorld::objectNames)
      .def(
          "object",
          [](const PlanningWorld& w, const std::string& name) {
            const db::ObjectDatabase* o = w.object(name);
            if (o == nullptr) throw InvalidArgument("name", "no object database '" + name + "'");
            return o;
          },
          py::arg("name"), py::return_value_policy::reference_internal,
          "An object database of the world by name.")
      .def(
          "checker",
          [](std::shared_ptr<PlanningWorld> w, const Scene& scene, const std::string& object,
             const std::optional<DoubleArray>& object_pose) {
            return std::make_unique<SceneChecker>(std::move(w), scene, object, object_pose);
          },
          py::arg("scene"), py::arg("object") = "", py::arg("object_pose") = py::none(),
          "A collision checker of the robot in `scene`, with `object` (default the scene's "
          "target) where the scene puts it or at object_pose (4 x 4).")
      .def(
          "ik",
          [](const PlanningWorld& w, const DoubleArray& pose, const std::string& link,
             const py::object& seed) { return solutionsOf(w, pose, link, seed); },
          py::arg("pose"), py::arg("link") = "palm", py::arg("seed") = py::int_(1),
          "Every arm IK solution (rows of num_arm_dofs) for a 4 x 4 pose of the palm or the "
          "flange in the robot's base frame.")
      .def("ik_batch", &ikBatch, py::arg("poses"), py::arg("link") = "palm",
           py::arg("seed") = py::int_(1),
           "The IK of an (N, 4, 4) array of poses in one call: (solutions (M, num_arm_dofs), "
           "pose_index (M,)), pose i solved with seed + i.")
      .def("__repr__", [](const PlanningWorld& w) {
        return "<hfts.World of '" + w.robot().name() + "' with " +
               std::to_string(w.objectNames().size()) + " objects>";
      });
}

}  // namespace hfts::python
