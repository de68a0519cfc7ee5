#pragma once
// The service's catalog of the bundled robot, the scenes' target objects
// and the scenes, built once per test program (the databases as
// bundledObject() gives them).

#include <memory>

#include "bundled_objects.h"
#include "grasp/hand_reachability.h"
#include "preprocess/database_builder.h"
#include "robot_fixture.h"
#include "service/planning_catalog.h"
#include "test_meshes.h"

namespace hfts::test {

/// The databases of the bundled scenes' targets: blob, bottle and mug.
inline const std::map<std::string, db::ObjectDatabase>& sceneTargetObjects() {
  static const std::map<std::string, db::ObjectDatabase> all = [] {
    std::map<std::string, db::ObjectDatabase> out;
    for (const char* mesh : {"blob.stl", "bottle.stl", "mug.ply"}) {
      auto database = bundledObject(bundledMeshDir() / mesh);
      out.emplace(database.name, std::move(database));
    }
    return out;
  }();
  return all;
}

inline std::map<std::string, robot::Scene> bundledScenes() {
  std::map<std::string, robot::Scene> scenes;
  for (const char* name : {"bin", "shelf", "table"})
    scenes.emplace(name,
                   robot::loadScene(sourcePath("objects/scenes/") / (name + std::string(".json"))));
  return scenes;
}

inline const service::PlanningCatalog& serviceCatalog() {
  static const service::PlanningCatalog catalog(
      std::make_shared<const planner::PlanningWorld>(kr5Sdh(), grasp::buildHandMap(kr5Sdh()),
                                                     sceneTargetObjects()),
      bundledScenes(), sourcePath("objects/scenes"));
  return catalog;
}

/// The KR5 + SDH (the default) and the Panda + gripper over the same
/// objects and scenes, as `hfts-server --robot A --robot B` serves them.
inline const service::PlanningCatalog& twoRobotCatalog() {
  static const service::PlanningCatalog catalog = [] {
    const robot::RobotModel panda =
        robot::RobotModel::load(sourcePath("robots/panda_gripper/panda_gripper.json"));
    auto kr5 = std::make_shared<const planner::PlanningWorld>(
        kr5Sdh(), grasp::buildHandMap(kr5Sdh()), sceneTargetObjects());
    auto second = std::make_shared<const planner::PlanningWorld>(
        panda, grasp::buildHandMap(panda, grasp::handMapOptions(panda)), kr5->objects());
    return service::PlanningCatalog({kr5, second}, bundledScenes(), sourcePath("objects/scenes"));
  }();
  return catalog;
}

}  // namespace hfts::test
