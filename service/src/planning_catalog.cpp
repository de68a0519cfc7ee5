#include "service/planning_catalog.h"

#include <algorithm>
#include <stdexcept>

namespace hfts::service {

namespace fs = std::filesystem;

namespace {

CatalogRobot catalogRobot(std::shared_ptr<const planner::PlanningWorld> world) {
  CatalogRobot r{std::move(world), {}, {}};
  const planner::PlanningWorld& w = *r.world;
  r.parameters = planner::plannerParameters(w);
  if (!w.robot().hasHand()) return r;  // an arm without a hand grasps nothing
  const int fingers = static_cast<int>(w.robot().fingertips().size());
  for (const std::string& name : w.objectNames())
    r.graspability.emplace(
        name, grasp::graspability(grasp::HftsSpace(*w.object(name), fingers), w.handMap(),
                                  w.thoroughHandMap(), grasp::objectiveOptions(w.robot())));
  return r;
}

}  // namespace

PlanningCatalog::PlanningCatalog(std::shared_ptr<const planner::PlanningWorld> world,
                                 std::map<std::string, robot::Scene> scenes, fs::path sceneDir,
                                 std::vector<std::string> skipped)
    : PlanningCatalog(std::vector<std::shared_ptr<const planner::PlanningWorld>>{std::move(world)},
                      std::move(scenes), std::move(sceneDir), std::move(skipped)) {}

PlanningCatalog::PlanningCatalog(std::vector<std::shared_ptr<const planner::PlanningWorld>> worlds,
                                 std::map<std::string, robot::Scene> scenes, fs::path sceneDir,
                                 std::vector<std::string> skipped)
    : scenes_(std::move(scenes)), scene_dir_(std::move(sceneDir)), skipped_(std::move(skipped)) {
  if (worlds.empty() || worlds.front() == nullptr)
    throw std::invalid_argument("a planning catalog needs at least one robot");
  const std::shared_ptr<const planner::ObjectLibrary> objects = worlds.front()->objects();
  for (auto& world : worlds) {
    if (world == nullptr) throw std::invalid_argument("a planning catalog got no world");
    if (world->objects() != objects)
      throw std::invalid_argument("the robots of a planning catalog must share their objects");
    if (findRobot(world->robot().name()) != nullptr)
      throw std::invalid_argument("two robots named '" + world->robot().name() + "'");
    robots_.push_back(catalogRobot(std::move(world)));
  }
}

std::shared_ptr<const PlanningCatalog> PlanningCatalog::load(const CatalogSources& sources) {
  if (!fs::is_directory(sources.scene_dir))
    throw std::runtime_error("scene directory " + sources.scene_dir.string() + " does not exist");
  if (sources.robot_configs.empty()) throw std::runtime_error("no robot config given");
  std::vector<std::string> skipped;
  std::vector<std::shared_ptr<const planner::PlanningWorld>> worlds;
  worlds.push_back(
      planner::PlanningWorld::load(sources.robot_configs.front(), sources.database_dir, &skipped));
  for (std::size_t i = 1; i < sources.robot_configs.size(); ++i) {
    worlds.push_back(planner::PlanningWorld::load(sources.robot_configs[i], sources.database_dir,
                                                  worlds.front()->objects()));
    for (std::size_t j = 0; j < i; ++j)
      if (worlds[j]->robot().name() == worlds[i]->robot().name())
        throw std::runtime_error(sources.robot_configs[i].string() + ": a second robot named '" +
                                 worlds[i]->robot().name() + "' (first from " +
                                 sources.robot_configs[j].string() + ")");
  }
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
  return std::make_shared<const PlanningCatalog>(std::move(worlds), std::move(scenes),
                                                 sources.scene_dir, std::move(skipped));
}

const CatalogRobot* PlanningCatalog::findRobot(const std::string& name) const {
  for (const CatalogRobot& r : robots_)
    if (r.name() == name) return &r;
  return nullptr;
}

std::vector<std::string> PlanningCatalog::robotNames() const {
  std::vector<std::string> names;
  for (const CatalogRobot& r : robots_) names.push_back(r.name());
  return names;
}

const robot::Scene* PlanningCatalog::scene(const std::string& name) const {
  const auto it = scenes_.find(name);
  return it == scenes_.end() ? nullptr : &it->second;
}

}  // namespace hfts::service
