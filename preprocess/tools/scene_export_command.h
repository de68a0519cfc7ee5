#pragma once
// `hfts-preprocess --export-scene`: a scene with robot and object as glTF.

#include <string>
#include <vector>

namespace hfts::preprocess {

struct SceneExportOptions {
  std::vector<double> config;  ///< empty: the scene's start, else the robot's home
  std::string robot;           ///< empty: the default robot
  std::string databases;       ///< empty: build/databases
};

/// Resolves a path that defaults to the repository: as given if it
/// exists, else relative to the repository the program was built in.
std::string repositoryPath(const std::string& given, const std::string& fallback,
                           const char* argv0);

/// Loads robot, scene and target database, checks the configuration and
/// writes the .glb. Returns the exit code; throws on errors (invalid
/// arguments as std::invalid_argument).
int exportSceneCommand(const std::vector<std::string>& args, const SceneExportOptions& options,
                       const char* argv0);

}  // namespace hfts::preprocess
