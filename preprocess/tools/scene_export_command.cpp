#include "scene_export_command.h"

#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "robot/robot_model.h"
#include "robot/scene.h"
#include "robot/scene_export.h"

namespace hfts::preprocess {

std::string repositoryPath(const std::string& given, const std::string& fallback,
                           const char* argv0) {
  if (!given.empty()) return given;
  if (std::filesystem::exists(fallback)) return fallback;
  // build/bin/hfts-preprocess -> the repository two levels up.
  std::error_code ec;
  const auto exe = std::filesystem::canonical(std::filesystem::path(argv0), ec);
  if (!ec) {
    const auto candidate = exe.parent_path().parent_path().parent_path() / fallback;
    if (std::filesystem::exists(candidate)) return candidate.string();
  }
  return fallback;
}

int exportSceneCommand(const std::vector<std::string>& args, const SceneExportOptions& options,
                       const char* argv0) {
  const robot::RobotModel model =
      robot::RobotModel::load(repositoryPath(options.robot, "robots/kr5_sdh/kr5_sdh.json", argv0));
  const robot::Scene scene = robot::loadScene(args.at(0));
  Eigen::VectorXd q = scene.startFor(model.name()).value_or(model.home());
  if (!options.config.empty())
    q = Eigen::Map<const Eigen::VectorXd>(options.config.data(),
                                          static_cast<Eigen::Index>(options.config.size()));
  std::string why;
  if (!model.withinLimits(q, 1e-9, &why)) throw std::invalid_argument("configuration " + why);
  const std::filesystem::path dbDir = repositoryPath(options.databases, "build/databases", argv0);
  const std::filesystem::path dbPath = dbDir / (scene.target_object + ".h5");
  if (!std::filesystem::exists(dbPath))
    throw std::runtime_error(
        "no database for target object '" + scene.target_object + "' in '" + dbDir.string() +
        "' (build it with hfts-preprocess objects/meshes -o " + dbDir.string() + ", or give --db)");
  const db::ObjectDatabase target = db::loadObjectDatabase(dbPath);
  robot::exportSceneGlb(model, scene, &target.geometry, q, args.at(1));
  std::cout << "wrote scene '" << scene.name << "' (" << scene.obstacles.size()
            << " obstacles, target '" << scene.target_object << "') to " << args.at(1) << "\n";
  return 0;
}

}  // namespace hfts::preprocess
