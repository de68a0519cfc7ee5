#include "fuzz_catalog.h"

#include <cstdlib>
#include <iostream>
#include <map>

#include "hfts_db/hand_map.h"
#include "hfts_db/object_database.h"

namespace hfts::fuzz {

std::filesystem::path sourcePath(const std::string& relative) {
  return std::filesystem::path(HFTS_SOURCE_DIR) / relative;
}

std::shared_ptr<const service::PlanningCatalog> catalog() {
  static const std::shared_ptr<const service::PlanningCatalog> built = [] {
    robot::RobotModel robot = robot::RobotModel::load(sourcePath("robots/kr5_sdh/kr5_sdh.json"));
    db::HandMap handMap = db::loadHandMap(sourcePath("tests/fuzz/corpus/hand_map/kr5_sdh_32.h5"));
    const db::ObjectDatabase object =
        db::loadObjectDatabase(sourcePath("tests/fuzz/corpus/object_database/small_cube.h5"));
    std::map<std::string, db::ObjectDatabase> objects;
    for (const char* name : {"blob", "bottle", "mug", "small_cube"}) {
      db::ObjectDatabase copy = object;
      copy.name = name;
      objects.emplace(name, std::move(copy));
    }
    std::map<std::string, robot::Scene> scenes;
    for (const char* name : {"bin", "shelf", "table"})
      scenes.emplace(name,
                     robot::loadScene(sourcePath("objects/scenes/" + std::string(name) + ".json")));
    auto world = std::make_shared<const planner::PlanningWorld>(
        std::move(robot), std::move(handMap), std::move(objects));
    return std::make_shared<const service::PlanningCatalog>(std::move(world), std::move(scenes),
                                                            sourcePath("objects/scenes"));
  }();
  return built;
}

void contractViolated(const std::string& what) {
  std::cerr << "contract violated: " << what << std::endl;
  std::abort();
}

}  // namespace hfts::fuzz
