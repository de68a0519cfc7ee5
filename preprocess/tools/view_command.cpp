#include "view_command.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>

#include "batch_runner.h"
#include "core/invalid_argument.h"
#include "preprocess/database_builder.h"
#include "robot/sensor_files.h"

namespace hfts::preprocess {

int viewCommand(const std::string& cloud, const std::string& outDir,
                const db::BuildParameters& params, double density, const ViewOptions& view,
                bool quiet) {
  const std::filesystem::path path(cloud);
  BatchOutcome outcome;
  outcome.mesh = path;
  outcome.name = path.stem().string();
  const auto start = std::chrono::steady_clock::now();
  try {
    const Vertices points = robot::readPointCloud(path) * params.scale;
    BuildResult result =
        buildObjectDatabaseFromView(points, nullptr, view, params, "view '" + path.string() + "'");
    db::ObjectDatabase& db = result.database;
    db.name = outcome.name;
    db.source_mesh = path.filename().string();
    db.source_sha256 = sha256File(path);
    db.density = density;
    std::filesystem::create_directories(outDir);
    db::saveObjectDatabase(db, std::filesystem::path(outDir) / (outcome.name + ".h5"));
    describeBuild(result, outcome);
  } catch (const InvalidArgument& e) {
    // The view's options are usage errors; the cloud's problems fail the build.
    for (const char* option : {"viewpoint", "hidden_depth", "floor"})
      if (e.field() == option) {
        std::string flag = std::string("--") + option;
        std::replace(flag.begin(), flag.end(), '_', '-');
        throw std::invalid_argument(flag + ": " + e.problem());
      }
    outcome.error = e.what();
  } catch (const std::exception& e) {
    outcome.error = e.what();
  }
  outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!quiet)
    for (const std::string& w : outcome.warnings) std::cerr << "warning: " << w << "\n";
  if (!outcome.ok) std::cerr << "hfts-preprocess: " << outcome.error << "\n";
  printSummaryTable(std::cout, {outcome});
  return outcome.ok ? 0 : 1;
}

}  // namespace hfts::preprocess
