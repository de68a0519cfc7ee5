#pragma once
// What the service plans with: the robot, its hand map, the object
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
  std::filesystem::path robot_config = "robots/kr5_sdh/kr5_sdh.json";
  std::filesystem::path database_dir = "build/databases";
  std::filesystem::path scene_dir = "objects/scenes";
};

/// The planning world plus the scenes by name and the planner's declared
/// parameters. Immutable once loaded: requests hold a shared_ptr to the
/// catalog they started with, so `reload` can swap in a new one while
/// plans run.
class PlanningCatalog {
 public:
  /// Loads the robot, `<robot>_hand_map.h5` and every other `*.h5` of the
  /// database directory (PlanningWorld::load) and every `*.json` scene of
  /// the scene directory, named by file stem. Object databases and scenes
  /// that fail to load are skipped and listed in skipped(). Throws
  /// std::runtime_error naming the file when the robot, the hand map or a
  /// directory cannot be read.
  static std::shared_ptr<const PlanningCatalog> load(const CatalogSources& sources);

  /// A catalog of an already built world (tests, benchmarks).
  PlanningCatalog(std::shared_ptr<const planner::PlanningWorld> world,
                  std::map<std::string, robot::Scene> scenes, std::filesystem::path sceneDir = {},
                  std::vector<std::string> skipped = {});

  const planner::PlanningWorld& world() const { return *world_; }
  const robot::RobotModel& robot() const { return world_->robot(); }
  /// nullptr for an unknown name.
  const robot::Scene* scene(const std::string& name) const;
  const std::map<std::string, robot::Scene>& scenes() const { return scenes_; }
  /// Where relative mesh paths of scenes are resolved.
  const std::filesystem::path& sceneDir() const { return scene_dir_; }
  const std::vector<planner::PlannerParameterInfo>& plannerParameters() const {
    return parameters_;
  }
  /// "<file>: <error>" for every database or scene that was skipped.
  const std::vector<std::string>& skipped() const { return skipped_; }
  /// How graspable each object is for the robot's hand in free space
  /// (grasp::graspability, 1000 leaf grasps, R(h) <= 5 mm), computed when
  /// the catalog is built (20-40 ms per object).
  const grasp::Graspability& graspability(const std::string& object) const {
    return graspability_.at(object);
  }

 private:
  std::shared_ptr<const planner::PlanningWorld> world_;
  std::map<std::string, robot::Scene> scenes_;
  std::filesystem::path scene_dir_;
  std::vector<planner::PlannerParameterInfo> parameters_;
  std::vector<std::string> skipped_;
  std::map<std::string, grasp::Graspability> graspability_;
};

}  // namespace hfts::service
