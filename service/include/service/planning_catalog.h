#pragma once
// What the service plans with: the robots, their hand maps, the object
// databases and the scenes, loaded once and shared by every request.

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "grasp/graspability.h"
#include "planner/grasp_motion_planner.h"
#include "robot/scene.h"

namespace hfts::service {

/// Where a catalog is loaded from.
struct CatalogSources {
  /// One config per robot; the first is the default of every request.
  std::vector<std::filesystem::path> robot_configs = {"robots/kr5_sdh/kr5_sdh.json"};
  std::filesystem::path database_dir = "build/databases";
  std::filesystem::path scene_dir = "objects/scenes";
};

/// One robot of a catalog: its planning world (which shares the catalog's
/// objects), the planner parameters with this robot's defaults and how
/// graspable each object is for its hand in free space
/// (grasp::graspability, 1000 leaf grasps, R(h) <= 5 mm; 20-40 ms per
/// object when the catalog is built).
struct CatalogRobot {
  std::shared_ptr<const planner::PlanningWorld> world;
  std::vector<planner::PlannerParameterInfo> parameters;
  std::map<std::string, grasp::Graspability> graspability;

  const robot::RobotModel& model() const { return world->robot(); }
  const std::string& name() const { return world->robot().name(); }
};

/// The planning worlds of one or more robots over the same objects, plus
/// the scenes by name. Immutable once loaded: requests hold a shared_ptr to
/// the catalog they started with, so `reload` can swap in a new one while
/// plans run.
class PlanningCatalog {
 public:
  /// Loads the object databases of the database directory once
  /// (planner::ObjectLibrary::load), every robot with its
  /// `<robot>_hand_map.h5` there, and every `*.json` scene of the scene
  /// directory, named by file stem. Object databases and scenes that fail
  /// to load are skipped and listed in skipped(). Throws
  /// std::runtime_error naming the file when a robot, a hand map or a
  /// directory cannot be read, or when two configs name the same robot.
  static std::shared_ptr<const PlanningCatalog> load(const CatalogSources& sources);

  /// A catalog of an already built world (tests, benchmarks).
  PlanningCatalog(std::shared_ptr<const planner::PlanningWorld> world,
                  std::map<std::string, robot::Scene> scenes, std::filesystem::path sceneDir = {},
                  std::vector<std::string> skipped = {});
  /// A catalog of several robots, the first the default; they must share
  /// one ObjectLibrary and have distinct names (std::invalid_argument).
  PlanningCatalog(std::vector<std::shared_ptr<const planner::PlanningWorld>> worlds,
                  std::map<std::string, robot::Scene> scenes, std::filesystem::path sceneDir = {},
                  std::vector<std::string> skipped = {});

  /// Every robot, the default first.
  const std::vector<CatalogRobot>& robots() const { return robots_; }
  /// nullptr for an unknown name.
  const CatalogRobot* findRobot(const std::string& name) const;
  std::vector<std::string> robotNames() const;

  /// The default robot's world, model, parameters and graspability.
  const planner::PlanningWorld& world() const { return *robots_.front().world; }
  const robot::RobotModel& robot() const { return robots_.front().model(); }
  /// nullptr for an unknown name.
  const robot::Scene* scene(const std::string& name) const;
  const std::map<std::string, robot::Scene>& scenes() const { return scenes_; }
  /// Where relative mesh paths of scenes are resolved.
  const std::filesystem::path& sceneDir() const { return scene_dir_; }
  const std::vector<planner::PlannerParameterInfo>& plannerParameters() const {
    return robots_.front().parameters;
  }
  /// "<file>: <error>" for every database or scene that was skipped.
  const std::vector<std::string>& skipped() const { return skipped_; }
  const grasp::Graspability& graspability(const std::string& object) const {
    return robots_.front().graspability.at(object);
  }

 private:
  std::vector<CatalogRobot> robots_;
  std::map<std::string, robot::Scene> scenes_;
  std::filesystem::path scene_dir_;
  std::vector<std::string> skipped_;
};

}  // namespace hfts::service
