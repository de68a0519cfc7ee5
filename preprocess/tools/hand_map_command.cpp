#include "hand_map_command.h"

#include <chrono>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "grasp/hand_map_builder.h"
#include "robot/robot_model.h"

namespace hfts::preprocess {

int handMapCommand(const std::string& robotConfig, const std::string& outDir,
                   unsigned long long seed) {
  const auto start = std::chrono::steady_clock::now();
  const robot::RobotModel model = robot::RobotModel::load(robotConfig);
  grasp::HandMapOptions options = grasp::handMapOptions(model);
  options.seed = seed;
  db::HandMap map = grasp::buildHandMap(model, options);
  map.producer = "hfts-preprocess --hand";
  std::error_code ec;
  std::filesystem::create_directories(outDir, ec);
  if (!std::filesystem::is_directory(outDir))
    throw std::runtime_error("cannot create output directory '" + outDir + "'");
  const std::filesystem::path path =
      std::filesystem::path(outDir) / (model.name() + "_hand_map.h5");
  db::saveHandMap(map, path);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "hand map of '" << model.name() << "': " << map.configurations.rows()
            << " grasp postures of " << map.num_draws << " drawn, "
            << std::filesystem::file_size(path) / 1024 << " KiB, " << seconds << " s -> "
            << path.string() << "\n";
  return 0;
}

}  // namespace hfts::preprocess
