#include "service/planning_catalog.h"

#include <algorithm>
#include <stdexcept>

namespace hfts::service {

namespace fs = std::filesystem;

PlanningCatalog::PlanningCatalog(std::shared_ptr<const planner::PlanningWorld> world,
                                 std::map<std::string, robot::Scene> scenes, fs::path sceneDir,
                                 std::vector<std::string> skipped)
    : world_(std::move(world)),
      scenes_(std::move(scenes)),
      scene_dir_(std::move(sceneDir)),
      parameters_(planner::plannerParameters(*world_)),
      skipped_(std::move(skipped)) {
  const int fingers = static_cast<int>(world_->robot().fingertips().size());
  for (const std::string& name : world_->objectNames())
    graspability_.emplace(
        name,
        grasp::graspability(grasp::HftsSpace(*world_->object(name), fingers), world_->handMap(),
                            world_->thoroughHandMap(), grasp::objectiveOptions(world_->robot())));
}

std::shared_ptr<const PlanningCatalog> PlanningCatalog::load(const CatalogSources& sources) {
  if (!fs::is_directory(sources.scene_dir))
    throw std::runtime_error("scene directory " + sources.scene_dir.string() + " does not exist");
  std::vector<std::string> skipped;
  auto world = planner::PlanningWorld::load(sources.robot_config, sources.database_dir, &skipped);
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(sources.scene_dir))
    if (e.is_regular_file() && e.path().extension() == ".json") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::map<std::string, robot::Scene> scenes;
  for (const fs::path& file : files) {
    const std::string name = file.stem().string();
    if (!robot::isSafeName(name)) {
      skipped.push_back(file.string() + ": the file name is not a valid scene name");
      continue;
    }
    try {
      robot::Scene scene = robot::loadScene(file);
      scene.name = name;  // requests name scenes by file, as hfts-bench does
      scenes.emplace(name, std::move(scene));
    } catch (const std::exception& e) {
      skipped.push_back(file.string() + ": " + e.what());
    }
  }
  return std::make_shared<const PlanningCatalog>(std::move(world), std::move(scenes),
                                                 sources.scene_dir, std::move(skipped));
}

const robot::Scene* PlanningCatalog::scene(const std::string& name) const {
  const auto it = scenes_.find(name);
  return it == scenes_.end() ? nullptr : &it->second;
}

}  // namespace hfts::service
