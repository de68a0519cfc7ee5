#include "view_command.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <iostream>

#include "batch_runner.h"
#include "core/invalid_argument.h"
#include "preprocess/database_builder.h"
#include "robot/point_cloud.h"
#include "robot/scene.h"
#include "robot/sensor_files.h"

namespace hfts::preprocess {

namespace {

/// Builds the views `read` gives into DIR/<name>.h5 (`sources` and the
/// hash of `first` recorded as the database's source) and reports as
/// viewCommand.
int buildViews(const std::function<std::vector<SensedView>()>& read, const std::string& sources,
               const std::filesystem::path& first, const std::string& name,
               const std::string& outDir, const db::BuildParameters& params, double density,
               bool quiet) {
  BatchOutcome outcome;
  outcome.mesh = first;
  outcome.name = name.empty() ? first.stem().string() : name;
  if (outcome.name.empty() || outcome.name.find('/') != std::string::npos)
    throw std::invalid_argument("--name '" + outcome.name + "' is no file stem");
  const auto start = std::chrono::steady_clock::now();
  try {
    BuildResult result =
        buildObjectDatabaseFromViews(read(), params, "views of '" + outcome.name + "'");
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

}  // namespace

int viewCommand(const std::vector<std::string>& clouds,
                const std::vector<Eigen::Vector3d>& viewpoints, const std::string& name,
                const std::string& outDir, const db::BuildParameters& params, double density,
                const ViewOptions& view, bool quiet) {
  if (clouds.size() != viewpoints.size())
    throw std::invalid_argument("give one --viewpoint per cloud (" + std::to_string(clouds.size()) +
                                " clouds, " + std::to_string(viewpoints.size()) + " viewpoints)");
  std::string sources;
  for (std::size_t i = 0; i < clouds.size(); ++i)
    sources += (i ? "," : "") + std::filesystem::path(clouds[i]).filename().string();
  const auto read = [&] {
    std::vector<SensedView> views;
    for (std::size_t i = 0; i < clouds.size(); ++i) {
      SensedView& v = views.emplace_back();
      robot::SensedPoints points = robot::readPointCloudWithNormals(clouds[i]);
      v.points = points.points * params.scale;
      v.normals = std::move(points.normals);
      v.options = view;
      v.options.viewpoint = viewpoints[i];
    }
    return views;
  };
  return buildViews(read, sources, clouds.front(), name, outDir, params, density, quiet);
}

int depthViewCommand(const std::string& scene, const std::string& name, const std::string& outDir,
                     const db::BuildParameters& params, double density, const ViewOptions& view,
                     bool quiet) {
  const auto read = [&] {
    std::vector<SensedView> views;
    for (robot::TargetView& seen : robot::loadTargetViews(scene)) {
      // The target's pixels, seen from the camera's centre.
      std::vector<std::uint8_t> others(seen.mask.size());
      for (std::size_t i = 0; i < others.size(); ++i) others[i] = seen.mask[i] == 0;
      const Vertices local = robot::depthToPoints(seen.image, seen.camera, &others);
      if (local.rows() < 4) {
        // Hidden or out of the frame here: a view that tells nothing of
        // the object's surface is left out (its carving would only help).
        if (!quiet)
          std::cerr << "warning: view '" << seen.name << "' sees " << local.rows()
                    << " pixels of the target (its mask), fewer than 4: left out\n";
        continue;
      }
      SensedView& v = views.emplace_back();
      v.points =
          (local * seen.pose.linear().transpose()).rowwise() + seen.pose.translation().transpose();
      v.options = view;
      v.options.viewpoint = seen.pose.translation();
      DepthEvidence& depth = v.depth.emplace();
      depth.camera = seen.pose;
      depth.fx = seen.camera.fx;
      depth.fy = seen.camera.fy;
      depth.cx = seen.camera.cx;
      depth.cy = seen.camera.cy;
      depth.width = seen.image.width;
      depth.height = seen.image.height;
      depth.depths = std::move(seen.image.depths);
      depth.target = std::move(seen.mask);
    }
    if (views.empty())
      throw InvalidArgument("points", "no view sees 4 or more pixels of the target (its mask)");
    return views;
  };
  const std::filesystem::path path(scene);
  return buildViews(read, path.filename().string(), path, name, outDir, params, density, quiet);
}

}  // namespace hfts::preprocess
