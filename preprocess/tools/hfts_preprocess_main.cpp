// hfts-preprocess: builds HFTS object databases from meshes, and inspects
// or exports existing ones. See docs/preprocess.md.
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <iostream>
#include <sstream>
#include <thread>

#include "batch_runner.h"
#include "database_summary.h"
#include "hand_map_command.h"
#include "preprocess/contact_export.h"
#include "preprocess/contact_filters.h"
#include "preprocess/database_builder.h"
#include "preprocess/object_sidecar.h"
#include "robot/fingertip_geometry.h"
#include "robot/robot_model.h"
#include "robot_check.h"
#include "scene_export_command.h"
#include "view_command.h"

namespace {

using hfts::db::BuildParameters;

void addBuildOptions(CLI::App& app, BuildParameters& p) {
  const auto positive = CLI::PositiveNumber;
  app.add_option("--scale", p.scale, "Multiply mesh coordinates by this (0.001 for mm)")
      ->check(positive)
      ->capture_default_str();
  app.add_option("--sample-density", p.sample_density, "Surface samples per square metre")
      ->check(positive)
      ->capture_default_str();
  app.add_option("--max-samples", p.max_samples,
                 "Cap on the area-uniform candidates drawn per object")
      ->check(CLI::Range(1u, 10000000u))
      ->capture_default_str();
  app.add_option("--viewpoints", p.viewpoints, "Directions of the visibility test")
      ->check(CLI::Range(8u, 4096u))
      ->capture_default_str();
  app.add_option("--pad-radius", p.pad_radius,
                 "Radius of the fingertip pad the filters are scaled to (m); see also --robot")
      ->check(positive)
      ->capture_default_str();
  app.add_option("--patch-radius", p.patch_radius,
                 "Normals, curvature and neighbours patch radius (m); 0 = pad radius / 2")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--filters", p.filters,
                 "Contact filters in order (curvature, concavity, clearance, neighbours; 'none' "
                 "for none)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--max-curvature", p.max_curvature, "Curvature filter: max surface variation")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--max-hull-distance", p.max_hull_distance,
                 "Concavity filter: max depth below the convex hull (m)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--min-neighbours", p.min_neighbours,
                 "Neighbours filter: min other contacts within the patch radius; 0 = a third of "
                 "the samples a patch holds")
      ->check(CLI::Range(0u, 1000000u))
      ->capture_default_str();
  app.add_option("--branching", p.branching, "Branching factor per level, e.g. 20,4,4")
      ->delimiter(',')
      ->check(CLI::Range(1u, 100000u))
      ->capture_default_str();
  app.add_option("--length-scale", p.length_scale, "k-means position scale (m); 0 = rho")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--normal-weight", p.normal_weight, "k-means weight of the normal")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--kmeans-iterations", p.kmeans_iterations, "Lloyd iterations per partition")
      ->check(CLI::Range(0u, 100000u))
      ->capture_default_str();
  app.add_option("--seed", p.seed, "Seed of sampling and clustering")->capture_default_str();
  app.add_option("--distance-grid-spacing", p.distance_grid_spacing,
                 "Distance grid node spacing (m); 0 = automatic")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--distance-grid-margin", p.distance_grid_margin,
                 "Distance grid extent beyond the bounding box on every side (m)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--convex-parts-max", p.convex_parts_max, "Convex decomposition: most parts")
      ->check(CLI::Range(1u, hfts::db::kMaxConvexParts))
      ->capture_default_str();
  app.add_option("--convex-parts-tolerance", p.convex_parts_tolerance,
                 "Convex decomposition: parts' volumes at most 1 + this times the solid's")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
}

int inspect(const std::string& file, bool json, const std::string& robotConfig) {
  const hfts::db::ObjectDatabase db = hfts::db::loadObjectDatabase(file);
  const auto graspability = hfts::preprocess::graspabilityReport(db, file, robotConfig);
  if (json)
    std::cout << hfts::preprocess::databaseSummaryJson(db, graspability).dump(2) << "\n";
  else
    std::cout << hfts::preprocess::databaseSummaryText(db, graspability);
  return 0;
}

int exportPly(const std::vector<std::string>& args) {
  const hfts::db::ObjectDatabase db = hfts::db::loadObjectDatabase(args.at(0));
  hfts::preprocess::exportContactsPly(db, args.at(1));
  std::cout << "wrote " << db.numContacts() << " contacts in " << db.levels.front().size()
            << " colours to " << args.at(1) << "\n";
  return 0;
}

/// The smallest fingertip pad of a robot (robot::smallestPadRadius): the
/// pad the database's filters are scaled to with --robot.
double padRadiusOf(const std::string& robotConfig, bool quiet) {
  const hfts::robot::RobotModel robot = hfts::robot::RobotModel::load(robotConfig);
  const double pad = hfts::robot::smallestPadRadius(robot);
  if (!(pad > 0.0))
    throw std::invalid_argument("--robot " + robotConfig + ": no fingertip of '" + robot.name() +
                                "' lies on the surface of its link's collision shapes, so it has "
                                "no pad radius to scale the filters to (give --pad-radius)");
  if (!quiet)
    std::cerr << "filters scaled to the smallest fingertip pad of " << robot.name() << ": "
              << 1000.0 * pad << " mm\n";
  return pad;
}

int build(const std::string& input, const std::string& outDir, BuildParameters params,
          double density, unsigned jobs, bool quiet) {
  hfts::preprocess::checkBuildParameters(params);
  hfts::preprocess::checkDensity(density, "density");
  const auto meshes = hfts::preprocess::collectMeshes(input);
  std::error_code ec;
  std::filesystem::create_directories(outDir, ec);
  if (!std::filesystem::is_directory(outDir))
    throw std::runtime_error("cannot create output directory '" + outDir + "'");
  const auto outcomes = hfts::preprocess::runBatch(meshes, outDir, params, density, jobs, std::cerr,
                                                   ::isatty(STDERR_FILENO) != 0, !quiet);
  hfts::preprocess::printSummaryTable(std::cout, outcomes);
  for (const auto& o : outcomes)
    if (!o.ok) return 1;
  return 0;
}

/// "x,y,z" as a point; throws std::invalid_argument naming `option`.
Eigen::Vector3d pointOf(const std::string& text, const char* option) {
  std::istringstream in(text);
  Eigen::Vector3d p;
  char comma1 = 0, comma2 = 0;
  if (!(in >> p.x() >> comma1 >> p.y() >> comma2 >> p.z()) || comma1 != ',' || comma2 != ',' ||
      !(in >> std::ws).eof() || !p.allFinite())
    throw std::invalid_argument(std::string(option) +
                                " expects X,Y,Z (three finite numbers), got '" + text + "'");
  return p;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Builds Hierarchical Fingertip Space databases (HDF5) from object meshes.\n"
      "  hfts-preprocess MESH_OR_DIR -o OUTDIR [options]\n"
      "  hfts-preprocess CLOUD.pcd|.ply... --viewpoint X,Y,Z... -o OUTDIR [options]\n"
      "  hfts-preprocess SCENE.json --depth-views -o OUTDIR [options]\n"
      "  hfts-preprocess --inspect FILE.h5 [--json]\n"
      "  hfts-preprocess --export-ply FILE.h5 OUT.ply\n"
      "  hfts-preprocess --check-robot ROBOT.json",
      "hfts-preprocess"};
  std::vector<std::string> inputs;
  std::string outDir, inspectFile, handConfig, checkConfig;
  std::vector<std::string> plyArgs, sceneArgs;
  hfts::preprocess::SceneExportOptions sceneOptions;
  bool json = false, quiet = false;
  unsigned jobs = std::max(1u, std::thread::hardware_concurrency());
  BuildParameters params;
  double density = hfts::db::kDefaultDensity;
  app.add_option("input", inputs,
                 "Mesh file or directory of meshes; or, with --viewpoint, the views of one object");
  app.add_option("-o,--output", outDir, "Directory for the <mesh stem>.h5 databases");
  app.add_option("-j,--jobs", jobs, "Objects built in parallel")
      ->check(CLI::Range(1u, 256u))
      ->capture_default_str();
  app.add_flag("-q,--quiet", quiet, "No progress output (warnings and errors still print)");
  auto* inspectOpt = app.add_option("--inspect", inspectFile, "Print a database's summary");
  app.add_flag("--json", json, "With --inspect: print JSON")->needs(inspectOpt);
  auto* plyOpt = app.add_option("--export-ply", plyArgs, "Write FILE.h5's contacts to OUT.ply")
                     ->expected(2)
                     ->type_name("FILE.h5 OUT.ply");
  auto* handOpt = app.add_option("--hand", handConfig,
                                 "Build the hand reachability map of ROBOT.json into -o DIR")
                      ->type_name("ROBOT.json");
  auto* checkOpt =
      app.add_option("--check-robot", checkConfig,
                     "Check ROBOT.json and its URDF for planning; exit 1 when something is wrong")
          ->type_name("ROBOT.json");
  auto* sceneOpt = app.add_option("--export-scene", sceneArgs,
                                  "Write SCENE.json with robot and object as binary glTF")
                       ->expected(2)
                       ->type_name("SCENE.json OUT.glb");
  app.add_option("--config", sceneOptions.config,
                 "With --export-scene: robot configuration (13 values, comma-separated)")
      ->delimiter(',')
      ->needs(sceneOpt);
  auto* robotOpt = app.add_option(
      "--robot", sceneOptions.robot,
      "Robot config: of --export-scene and of --inspect's graspability (default "
      "robots/kr5_sdh/kr5_sdh.json); when building, the filters are scaled to its smallest "
      "fingertip pad instead of --pad-radius");
  app.add_option("--db", sceneOptions.databases,
                 "With --export-scene: directory of object databases (default build/databases)")
      ->needs(sceneOpt);
  std::vector<std::string> viewpoints;
  hfts::preprocess::ViewOptions view;
  auto* viewOpt =
      app.add_option("--viewpoint", viewpoints,
                     "The inputs are segmented views of one object (PCD or PLY points, z up), "
                     "the first seen from the first camera centre X,Y,Z given, and so on "
                     "(repeat it; docs/point_clouds.md)")
          ->type_name("X,Y,Z");
  bool depthViews = false;
  auto* depthViewsOpt = app.add_flag(
      "--depth-views", depthViews,
      "The input is a scene file whose depth_image obstacles with a mask are views of one "
      "object (the masked pixels); their whole images carve where it may be "
      "(docs/point_clouds.md)");
  depthViewsOpt->excludes(viewOpt);
  const std::vector<std::string> viewOnly{"--hidden-depth", "--name", "--smoothing", "--floor"};
  app.add_option("--hidden-depth", view.hidden_depth,
                 "With --viewpoint or --depth-views: how far beyond the observed points the "
                 "unseen side may reach (m); 0 = the largest edge of the points' bounding box")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  std::string objectName;
  app.add_option("--name", objectName,
                 "With --viewpoint or --depth-views: the object's name, and its database's "
                 "stem (default: the first input's stem)");
  app.add_option("--smoothing", view.smoothing,
                 "With --viewpoint or --depth-views: radius (m) of the moving-least-squares "
                 "smoothing of the sensor's noise; 0 = none")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--floor", view.floor,
                 "With --viewpoint or --depth-views: height (z) the object stands on (default: "
                 "its lowest point; with --depth-views the highest horizontal plane seen there)");
  addBuildOptions(app, params);
  app.add_option("--density", density,
                 "Density of the objects' material (kg/m^3); a <mesh stem>.json sidecar with "
                 "{\"density\": ...} overrides it for its mesh")
      ->check(CLI::Range(hfts::db::kMinDensity, hfts::db::kMaxDensity))
      ->capture_default_str();
  app.get_option("--pad-radius")->excludes(robotOpt);
  app.set_version_flag("--version", hfts::preprocess::producerName());
  inspectOpt->excludes(plyOpt);
  handOpt->excludes(inspectOpt)->excludes(plyOpt)->excludes(sceneOpt);
  checkOpt->excludes(inspectOpt)->excludes(plyOpt)->excludes(sceneOpt)->excludes(handOpt);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every usage error exits 2.
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (!inspectFile.empty())
      return inspect(inspectFile, json,
                     hfts::preprocess::repositoryPath(sceneOptions.robot,
                                                      "robots/kr5_sdh/kr5_sdh.json", argv[0]));
    if (!plyArgs.empty()) return exportPly(plyArgs);
    if (!checkConfig.empty())
      return hfts::preprocess::printRobotFindings(hfts::preprocess::checkRobot(checkConfig),
                                                  std::cout);
    if (!handConfig.empty()) {
      if (outDir.empty()) throw std::invalid_argument("--hand needs -o DIR");
      return hfts::preprocess::handMapCommand(handConfig, outDir, params.seed);
    }
    if (!sceneArgs.empty())
      return hfts::preprocess::exportSceneCommand(sceneArgs, sceneOptions, argv[0]);
    for (const std::string& option : viewOnly)
      if (app.count(option) > 0 && viewpoints.empty() && !depthViews)
        throw std::invalid_argument(option + " needs --viewpoint or --depth-views");
    if (inputs.empty() || outDir.empty()) {
      std::cerr << "hfts-preprocess: give a mesh or directory and -o OUTDIR (see --help)\n";
      return 2;
    }
    if (!sceneOptions.robot.empty()) params.pad_radius = padRadiusOf(sceneOptions.robot, quiet);
    if (params.filters.size() == 1 && params.filters[0] == "none") params.filters.clear();
    if (!viewpoints.empty()) {
      std::vector<Eigen::Vector3d> centres;
      for (const std::string& text : viewpoints) centres.push_back(pointOf(text, "--viewpoint"));
      return hfts::preprocess::viewCommand(inputs, centres, objectName, outDir, params, density,
                                           view, quiet);
    }
    if (depthViews) {
      if (inputs.size() != 1) throw std::invalid_argument("--depth-views takes one scene file");
      return hfts::preprocess::depthViewCommand(inputs.front(), objectName, outDir, params, density,
                                                view, quiet);
    }
    if (inputs.size() != 1)
      throw std::invalid_argument(
          "give one mesh or directory (several inputs are the views "
          "of one object, with --viewpoint)");
    return build(inputs.front(), outDir, params, density, jobs, quiet);
  } catch (const std::invalid_argument& e) {
    std::cerr << "hfts-preprocess: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "hfts-preprocess: " << e.what() << "\n";
    return 1;
  }
}
