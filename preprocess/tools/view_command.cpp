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

int viewCommand(const std::vector<std::string>& clouds,
                const std::vector<Eigen::Vector3d>& viewpoints, const std::string& name,
                const std::string& outDir, const db::BuildParameters& params, double density,
                const ViewOptions& view, bool quiet) {
  if (clouds.size() != viewpoints.size())
    throw std::invalid_argument("give one --viewpoint per cloud (" + std::to_string(clouds.size()) +
                                " clouds, " + std::to_string(viewpoints.size()) + " viewpoints)");
  const std::filesystem::path first(clouds.front());
  BatchOutcome outcome;
  outcome.mesh = first;
  outcome.name = name.empty() ? first.stem().string() : name;
  if (outcome.name.empty() || outcome.name.find('/') != std::string::npos)
    throw std::invalid_argument("--name '" + outcome.name + "' is no file stem");
  const auto start = std::chrono::steady_clock::now();
  try {
    std::vector<SensedView> views;
    std::string sources;
    for (std::size_t i = 0; i < clouds.size(); ++i) {
      SensedView& v = views.emplace_back();
      robot::SensedPoints read = robot::readPointCloudWithNormals(clouds[i]);
      v.points = read.points * params.scale;
      v.normals = std::move(read.normals);
      v.options = view;
      v.options.viewpoint = viewpoints[i];
      sources += (i ? "," : "") + std::filesystem::path(clouds[i]).filename().string();
    }
    BuildResult result =
        buildObjectDatabaseFromViews(views, params, "views of '" + outcome.name + "'");
    db::ObjectDatabase& db = result.database;
    db.name = outcome.name;
    db.source_mesh = sources;
    db.source_sha256 = sha256File(first);
    db.density = density;
    std::filesystem::create_directories(outDir);
    db::saveObjectDatabase(db, std::filesystem::path(outDir) / (outcome.name + ".h5"));
    describeBuild(result, outcome);
  } catch (const InvalidArgument& e) {
    // The views' options are usage errors; the clouds' problems fail the build.
    for (const char* option : {"viewpoint", "hidden_depth", "floor", "smoothing"}) {
      const std::string field = e.field();
      if (field.size() >= std::string(option).size() &&
          field.compare(field.size() - std::string(option).size(), std::string::npos, option) ==
              0) {
        std::string flag = std::string("--") + option;
        std::replace(flag.begin(), flag.end(), '_', '-');
        throw std::invalid_argument(flag + " (" + field + "): " + e.problem());
      }
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
