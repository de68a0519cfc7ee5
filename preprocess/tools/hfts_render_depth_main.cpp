// hfts-render-depth: what a depth camera would see of a scene
// (docs/point_clouds.md). Writes the depth image (16-bit PNG, mm), the
// target's segmentation mask (8-bit PNG) and a scene that has the view in
// place of the obstacles, to plan from what the camera saw; with
// --partial, the target's points (PLY) and a scene whose target is the
// object built from them.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/invalid_argument.h"
#include "hfts_db/object_database.h"
#include "robot/depth_renderer.h"
#include "robot/scene.h"
#include "robot/sensor_files.h"
#include "scene_export_command.h"

namespace {

using namespace hfts;
using nlohmann::json;
namespace fs = std::filesystem;

json poseJson(const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond q(pose.linear());
  const Eigen::Vector3d t = pose.translation();
  return {{"position", {t.x(), t.y(), t.z()}}, {"orientation", {q.x(), q.y(), q.z(), q.w()}}};
}

Eigen::Vector3d point(const std::vector<double>& values, const char* what) {
  if (values.size() != 3) throw std::invalid_argument(std::string(what) + " needs x,y,z");
  return {values[0], values[1], values[2]};
}

struct Options {
  std::string scene, output, databases, placement = "target", stem;
  std::vector<double> eye, centre;
  int width = 640, height = 480;
  double fov = 58.0;  // degrees, horizontal (a Kinect-class camera)
  std::string noise = "kinect";
  std::uint64_t seed = 1;
  double voxel = robot::CloudOptions{}.voxel, radius = robot::CloudOptions{}.radius;
  bool partial = false;  ///< also the target's points and a scene to grasp them
};

void writePartial(const Options& o, const std::string& stem, const robot::DepthView& view,
                  const robot::RenderedDepth& rendered, const json& out,
                  const std::string& sceneName);

int run(const Options& o, const char* argv0) {
  const robot::Scene all = robot::loadScene(o.scene);
  const robot::Scene scene = all.withPlacement(o.placement);
  const fs::path dbDir = preprocess::repositoryPath(o.databases, "build/databases", argv0);
  const fs::path dbPath = dbDir / (scene.target_object + ".h5");
  if (!fs::exists(dbPath))
    throw std::runtime_error("no database for target object '" + scene.target_object + "' in '" +
                             dbDir.string() + "' (give --db)");
  const db::ObjectDatabase target = db::loadObjectDatabase(dbPath);
  const TriangleMesh mesh{target.geometry.mesh_vertices, target.geometry.mesh_triangles};
  const Eigen::Isometry3d targetPose = robot::targetPose(scene, mesh.vertices);
  robot::DepthView view =
      robot::DepthView::withFieldOfView(o.width, o.height, o.fov * 3.14159265358979323846 / 180);
  view.pose = robot::lookAt(point(o.eye, "--eye"), point(o.centre, "--look-at"));
  robot::DepthNoise noise = o.noise == "none" ? robot::DepthNoise::none() : robot::DepthNoise{};
  noise.seed = o.seed;
  const robot::RenderedDepth rendered = robot::renderDepth(scene, &mesh, targetPose, view, noise);

  const std::string stem = o.stem.empty() ? scene.name + "_view" : o.stem;
  fs::create_directories(o.output);
  core::writeFileAtomically(fs::path(o.output) / (stem + ".png"),
                            robot::encodeDepthPng(rendered.image));
  core::writeFileAtomically(fs::path(o.output) / (stem + "_mask.png"),
                            robot::encodeMaskPng(rendered.target_mask, o.width, o.height));
  // The scene as the camera saw it: one depth_image obstacle, the target
  // where it stood (its support, if any, is now in the image).
  std::ifstream in(o.scene);
  json out = json::parse(in);
  out["name"] = stem;
  out["description"] = "scene '" + scene.name + "' seen by hfts-render-depth";
  out["obstacles"] = json::array({json{{"name", "view"},
                                       {"type", "depth_image"},
                                       {"pose", poseJson(view.pose)},
                                       {"file", stem + ".png"},
                                       {"units", "mm"},
                                       {"mask", stem + "_mask.png"},
                                       {"intrinsics",
                                        {{"fx", view.camera.fx},
                                         {"fy", view.camera.fy},
                                         {"cx", view.camera.cx},
                                         {"cy", view.camera.cy}}},
                                       {"max_depth", view.camera.max_depth},
                                       {"voxel", o.voxel},
                                       {"radius", o.radius}}});
  out["target"] = {{"object", scene.target_object}, {"pose", poseJson(targetPose)}};
  out.erase("placements");
  core::writeFileAtomically(fs::path(o.output) / (stem + ".json"), out.dump(2) + "\n");
  std::size_t seen = 0, onTarget = 0;
  for (std::size_t i = 0; i < rendered.image.depths.size(); ++i) {
    seen += rendered.image.depths[i] > 0 ? 1 : 0;
    onTarget += rendered.target_mask[i];
  }
  std::cout << "wrote " << stem << ".png, " << stem << "_mask.png, " << stem << ".json";
  if (o.partial) writePartial(o, stem, view, rendered, out, scene.name);
  std::cout << " to " << o.output << ": " << seen << " of " << rendered.image.depths.size()
            << " pixels with a depth, " << onTarget << " on the target\n";
  return 0;
}

/// What the camera saw of the target alone (world frame, metres): the
/// segmented cloud hfts-preprocess --viewpoint builds an object from, and
/// the view's scene with that object where it stood (its frame is the
/// world's).
void writePartial(const Options& o, const std::string& stem, const robot::DepthView& view,
                  const robot::RenderedDepth& rendered, const json& out,
                  const std::string& sceneName) {
  std::vector<std::uint8_t> offTarget(rendered.target_mask.size());
  for (std::size_t i = 0; i < offTarget.size(); ++i)
    offTarget[i] = rendered.target_mask[i] != 0 ? 0 : 1;
  const Vertices seenOfTarget = robot::depthToPoints(rendered.image, view.camera, &offTarget);
  std::ostringstream ply;
  ply << "ply\nformat ascii 1.0\ncomment hfts-render-depth: the target seen from " << o.eye[0]
      << "," << o.eye[1] << "," << o.eye[2] << "\nelement vertex " << seenOfTarget.rows()
      << "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  ply.precision(7);
  for (Eigen::Index i = 0; i < seenOfTarget.rows(); ++i) {
    const Eigen::Vector3d p = view.pose * Eigen::Vector3d(seenOfTarget.row(i).transpose());
    ply << p.x() << " " << p.y() << " " << p.z() << "\n";
  }
  core::writeFileAtomically(fs::path(o.output) / (stem + "_object.ply"), ply.str());
  json partial = out;
  partial["name"] = stem + "_partial";
  partial["description"] =
      "scene '" + sceneName + "' seen by hfts-render-depth, its target built from the view alone";
  partial["target"] = {{"object", stem + "_object"},
                       {"pose", poseJson(Eigen::Isometry3d::Identity())}};
  core::writeFileAtomically(fs::path(o.output) / (stem + "_partial.json"), partial.dump(2) + "\n");
  std::cout << ", " << stem << "_object.ply, " << stem << "_partial.json";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Render what a depth camera sees of a scene; write the image, the target's "
      "mask and a scene to plan from them"};
  Options o;
  app.add_option("scene", o.scene, "Scene file")->required()->check(CLI::ExistingFile);
  app.add_option("-o,--output", o.output, "Directory for the outputs")->required();
  app.add_option("--db", o.databases, "Directory of object databases (default build/databases)");
  app.add_option("--placement", o.placement, "Where the target stands")->capture_default_str();
  app.add_option("--eye", o.eye, "Camera position x,y,z (m, world)")->required()->delimiter(',');
  app.add_option("--look-at", o.centre, "Point the camera looks at, x,y,z")
      ->required()
      ->delimiter(',');
  app.add_option("--width", o.width, "Image width (pixels)")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  app.add_option("--height", o.height, "Image height (pixels)")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  app.add_option("--fov", o.fov, "Horizontal field of view (degrees)")
      ->check(CLI::Range(1.0, 170.0))
      ->capture_default_str();
  app.add_option("--noise", o.noise, "kinect (axial noise, grazing angles, dropouts) or none")
      ->check(CLI::IsMember({"kinect", "none"}))
      ->capture_default_str();
  app.add_option("--seed", o.seed, "Seed of the noise")->capture_default_str();
  app.add_option("--name", o.stem, "Stem of the output files (default <scene>_view)");
  app.add_option("--voxel", o.voxel, "The written scene's voxel (m)")->capture_default_str();
  app.add_option("--radius", o.radius, "The written scene's noise radius (m)")
      ->capture_default_str();
  app.add_flag("--partial", o.partial,
               "Also write the target's points (<stem>_object.ply, world frame) and a scene "
               "whose target is the object hfts-preprocess --viewpoint builds from them "
               "(<stem>_partial.json)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    return run(o, argv[0]);
  } catch (const std::invalid_argument& e) {
    std::cerr << "hfts-render-depth: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "hfts-render-depth: " << e.what() << "\n";
    return 1;
  }
}
