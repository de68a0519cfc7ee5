#include "planner/planning_world.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "planner_parameters.h"
#include "robot/collision_checker.h"
#include "robot/fingertip_geometry.h"
#include "robot/object_surface.h"

namespace hfts::planner {

namespace fs = std::filesystem;

ObjectLibrary::ObjectLibrary(std::map<std::string, db::ObjectDatabase> objects)
    : objects_(std::move(objects)) {
  for (const auto& [name, database] : objects_) {
    collision_meshes_.emplace(
        name, std::make_unique<const robot::CollisionMesh>(
                  TriangleMesh{database.geometry.mesh_vertices, database.geometry.mesh_triangles}));
    surfaces_.emplace(name, std::make_unique<const robot::ObjectSurface>(database.geometry));
  }
}

ObjectLibrary::~ObjectLibrary() = default;

std::shared_ptr<const ObjectLibrary> ObjectLibrary::load(const fs::path& dbDir,
                                                         std::vector<std::string>* skipped) {
  if (!fs::is_directory(dbDir))
    throw std::runtime_error("database directory " + dbDir.string() + " does not exist");
  // Hand maps of every robot (<robot name>_hand_map.h5) share the folder
  // with the object databases.
  const auto isHandMap = [](const fs::path& file) {
    const std::string name = file.filename().string();
    const std::string suffix = "_hand_map.h5";
    return name.size() > suffix.size() &&
           name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(dbDir))
    if (e.is_regular_file() && e.path().extension() == ".h5" && !isHandMap(e.path()))
      files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::map<std::string, db::ObjectDatabase> objects;
  for (const fs::path& file : files) {
    try {
      db::ObjectDatabase database = db::loadObjectDatabase(file);
      const std::string name = database.name;
      if (!objects.emplace(name, std::move(database)).second)
        throw std::runtime_error("a second database of object '" + name + "'");
    } catch (const std::exception& e) {
      if (skipped != nullptr) skipped->push_back(file.string() + ": " + e.what());
    }
  }
  return std::make_shared<const ObjectLibrary>(std::move(objects));
}

const db::ObjectDatabase* ObjectLibrary::object(const std::string& name) const {
  const auto it = objects_.find(name);
  return it == objects_.end() ? nullptr : &it->second;
}

const robot::CollisionMesh* ObjectLibrary::collisionMesh(const std::string& name) const {
  const auto it = collision_meshes_.find(name);
  return it == collision_meshes_.end() ? nullptr : it->second.get();
}

const robot::ObjectSurface* ObjectLibrary::surface(const std::string& name) const {
  const auto it = surfaces_.find(name);
  return it == surfaces_.end() ? nullptr : it->second.get();
}

std::vector<std::string> ObjectLibrary::names() const {
  std::vector<std::string> names;
  for (const auto& entry : objects_) names.push_back(entry.first);
  return names;
}

PlanningWorld::PlanningWorld(robot::RobotModel robot, db::HandMap handMap,
                             std::map<std::string, db::ObjectDatabase> objects)
    : PlanningWorld(std::move(robot), std::move(handMap),
                    std::make_shared<const ObjectLibrary>(std::move(objects))) {}

PlanningWorld::PlanningWorld(robot::RobotModel robot, db::HandMap handMap,
                             std::shared_ptr<const ObjectLibrary> objects)
    : robot_(std::move(robot)),
      collision_(robot::buildCollisionModel(robot_)),
      bound_(robot_),
      ik_(robot_),
      fast_(std::in_place, robot_, handMap),
      thorough_(std::in_place, robot_, std::move(handMap), grasp::HandQueryOptions::thorough()),
      objects_(std::move(objects)),
      padRadius_(robot::smallestPadRadius(robot_)) {
  if (objects_ == nullptr) throw std::invalid_argument("PlanningWorld: no object library");
}

PlanningWorld::PlanningWorld(robot::RobotModel robot, std::shared_ptr<const ObjectLibrary> objects)
    : robot_(std::move(robot)),
      collision_(robot::buildCollisionModel(robot_)),
      bound_(robot_),
      ik_(robot_),
      objects_(std::move(objects)) {
  if (robot_.hasHand())
    throw robot::ModelError("robot '" + robot_.name() + "' has a hand: its world needs a hand map");
  if (objects_ == nullptr) throw std::invalid_argument("PlanningWorld: no object library");
}

PlanningWorld::PlanningWorld(std::shared_ptr<const robot::CollisionModel> model,
                             std::shared_ptr<const ObjectLibrary> objects)
    : robot_(model != nullptr ? model->robot
                              : throw std::invalid_argument("PlanningWorld: no collision model")),
      collision_(std::move(model)),
      bound_(robot_),
      ik_(robot_),
      objects_(std::move(objects)) {
  if (objects_ == nullptr) throw std::invalid_argument("PlanningWorld: no object library");
}

PlanningWorld::~PlanningWorld() = default;

const grasp::HandReachability& PlanningWorld::handMap() const {
  if (!fast_) throw std::logic_error("robot '" + robot_.name() + "' has no hand (no hand map)");
  return *fast_;
}

const grasp::HandReachability& PlanningWorld::thoroughHandMap() const {
  if (!thorough_) throw std::logic_error("robot '" + robot_.name() + "' has no hand (no hand map)");
  return *thorough_;
}

namespace {

/// The world of the robot config with its hand map from `dbDir` (an arm
/// without a hand: none), errors naming the file.
std::shared_ptr<const PlanningWorld> worldOf(const fs::path& robotConfig, const fs::path& dbDir,
                                             std::shared_ptr<const ObjectLibrary> objects) {
  robot::RobotModel robot = robot::RobotModel::load(robotConfig);
  if (!robot.hasHand()) return std::make_shared<const PlanningWorld>(std::move(robot), objects);
  const fs::path mapPath = dbDir / (robot.name() + "_hand_map.h5");
  if (!fs::exists(mapPath))
    throw std::runtime_error("no hand reachability map " + mapPath.string() +
                             " (build it with: hfts-preprocess --hand " + robotConfig.string() +
                             " -o " + dbDir.string() + ")");
  return std::make_shared<const PlanningWorld>(std::move(robot), db::loadHandMap(mapPath),
                                               std::move(objects));
}

}  // namespace

std::shared_ptr<const PlanningWorld> PlanningWorld::load(const fs::path& robotConfig,
                                                         const fs::path& dbDir,
                                                         std::vector<std::string>* skipped) {
  auto world = worldOf(robotConfig, dbDir, ObjectLibrary::load(dbDir, skipped));
  quietOmpl();
  defaultSettings(world->robot());  // the config's planner_defaults, checked now
  return world;
}

std::shared_ptr<const PlanningWorld> PlanningWorld::load(
    const fs::path& robotConfig, const fs::path& dbDir,
    std::shared_ptr<const ObjectLibrary> objects) {
  if (!fs::is_directory(dbDir))
    throw std::runtime_error("database directory " + dbDir.string() + " does not exist");
  auto world = worldOf(robotConfig, dbDir, std::move(objects));
  quietOmpl();
  defaultSettings(world->robot());
  return world;
}

}  // namespace hfts::planner
