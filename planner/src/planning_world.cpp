#include "planner/planning_world.h"

#include <algorithm>
#include <stdexcept>

#include "robot/collision_checker.h"
#include "robot/fingertip_geometry.h"

namespace hfts::planner {

PlanningWorld::PlanningWorld(robot::RobotModel robot, db::HandMap handMap,
                             std::map<std::string, db::ObjectDatabase> objects)
    : robot_(std::move(robot)),
      ik_(robot_),
      fast_(robot_, handMap),
      thorough_(robot_, std::move(handMap), grasp::HandQueryOptions::thorough()),
      objects_(std::move(objects)),
      padRadius_(robot::smallestPadRadius(robot_)) {
  robot_.spheres();  // built now, not in the first plan's time
  for (const auto& [name, database] : objects_)
    collisionMeshes_.emplace(
        name, std::make_unique<const robot::CollisionMesh>(
                  TriangleMesh{database.geometry.mesh_vertices, database.geometry.mesh_triangles}));
}

PlanningWorld::~PlanningWorld() = default;

std::shared_ptr<const PlanningWorld> PlanningWorld::load(const std::filesystem::path& robotConfig,
                                                         const std::filesystem::path& dbDir,
                                                         std::vector<std::string>* skipped) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(dbDir))
    throw std::runtime_error("database directory " + dbDir.string() + " does not exist");
  robot::RobotModel robot = robot::RobotModel::load(robotConfig);
  const fs::path mapPath = dbDir / (robot.name() + "_hand_map.h5");
  if (!fs::exists(mapPath))
    throw std::runtime_error("no hand reachability map " + mapPath.string() +
                             " (build it with: hfts-preprocess --hand " + robotConfig.string() +
                             " -o " + dbDir.string() + ")");
  db::HandMap map = db::loadHandMap(mapPath);
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
  return std::make_shared<const PlanningWorld>(std::move(robot), std::move(map),
                                               std::move(objects));
}

const db::ObjectDatabase* PlanningWorld::object(const std::string& name) const {
  const auto it = objects_.find(name);
  return it == objects_.end() ? nullptr : &it->second;
}

const robot::CollisionMesh* PlanningWorld::collisionMesh(const std::string& name) const {
  const auto it = collisionMeshes_.find(name);
  return it == collisionMeshes_.end() ? nullptr : it->second.get();
}

std::vector<std::string> PlanningWorld::objectNames() const {
  std::vector<std::string> names;
  for (const auto& entry : objects_) names.push_back(entry.first);
  return names;
}

}  // namespace hfts::planner
