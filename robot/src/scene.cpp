#include "robot/scene.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <optional>
#include <set>
#include <sstream>

#include "core/base64.h"
#include "core/invalid_argument.h"
#include "json_numbers.h"
#include "robot/sensor_files.h"

namespace hfts::robot {
namespace {

using nlohmann::json;

/// `where` + "." + `key`, or `key` at the top.
std::string pathOf(const std::string& where, const std::string& key) {
  return where.empty() ? key : where + "." + key;
}

/// Field access that names the field's path in every error.
class Fields {
 public:
  Fields(const json& object, std::string where, const std::string& source)
      : object_(object), where_(std::move(where)), source_(source) {
    if (!object_.is_object()) fail("must be a JSON object");
  }
  /// A problem of this object as a whole.
  [[noreturn]] void fail(const std::string& problem) const {
    throw SceneError(source_, where_, problem);
  }
  /// A problem of its member `key`.
  [[noreturn]] void failAt(const std::string& key, const std::string& problem) const {
    throw SceneError(source_, pathOf(where_, key), problem);
  }
  bool has(const char* key) const { return object_.contains(key); }
  const json& at(const char* key) const {
    if (!has(key)) failAt(key, "is required");
    return object_.at(key);
  }
  std::string string(const char* key) const {
    if (!at(key).is_string()) failAt(key, "must be a string");
    return at(key).get<std::string>();
  }
  /// Member `key` if present, else `fallback`; a present one must be a
  /// finite number >= 0.
  double nonNegative(const char* key, double fallback) const {
    if (!has(key)) return fallback;
    const json& v = at(key);
    if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0)
      failAt(key, "must be a number >= 0");
    return v.get<double>();
  }
  double number(const char* key) const {
    const json& v = at(key);
    if (!v.is_number() || !std::isfinite(v.get<double>())) failAt(key, "must be a number");
    return v.get<double>();
  }
  double positive(const char* key) const {
    const json& v = at(key);
    if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() <= 0)
      failAt(key, "must be a positive number");
    return v.get<double>();
  }
  Eigen::VectorXd numbers(const char* key, Eigen::Index n) const {
    std::string problem;
    std::optional<Eigen::VectorXd> values = finiteNumbers(at(key), n, problem);
    if (!values) failAt(key, problem);
    return *values;
  }
  Eigen::Isometry3d pose(const char* key) const {
    const Fields p(at(key), pathOf(where_, key), source_);
    Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
    out.translation() = p.numbers("position", 3);
    const Eigen::VectorXd q = p.numbers("orientation", 4);  // x, y, z, w (ROS order)
    if (q.norm() < 1e-9) p.failAt("orientation", "is a quaternion of zero norm");
    out.linear() = Eigen::Quaterniond(q(3), q(0), q(1), q(2)).normalized().toRotationMatrix();
    return out;
  }

 private:
  const json& object_;
  std::string where_;
  const std::string& source_;
};

/// The cloud options of a points or depth_image obstacle (defaults:
/// CloudOptions). A depth image's camera is its viewpoint (the obstacle
/// frame's origin); a cloud's is `viewpoint` when it gives one.
CloudOptions cloudOptions(const Fields& f, const std::string& type, const std::string& where,
                          const std::string& source, const json& item) {
  CloudOptions options;
  options.voxel = f.has("voxel") ? f.positive("voxel") : options.voxel;
  options.radius = f.nonNegative("radius", options.radius);
  options.shadow = f.nonNegative("shadow", options.shadow);
  if (type == "depth_image") options.viewpoint = Eigen::Vector3d::Zero();
  if (type == "points" && f.has("viewpoint")) options.viewpoint = f.numbers("viewpoint", 3);
  if (f.has("outliers")) {
    const Fields o(item.at("outliers"), pathOf(where, "outliers"), source);
    options.remove_outliers = true;
    const double neighbours = o.positive("neighbours");
    if (neighbours > 1000 || neighbours != std::floor(neighbours))
      o.failAt("neighbours", "must be a whole number from 1 to 1000");
    options.outlier_neighbours = static_cast<int>(neighbours);
    options.outlier_stddev = o.positive("stddev");
  }
  return options;
}

/// `points`: [[x, y, z], ...] in the obstacle's frame.
Vertices inlinePoints(const Fields& f, const json& points) {
  if (!points.is_array() || points.empty()) f.failAt("points", "must be a non-empty array");
  Vertices out(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::string problem;
    const std::optional<Eigen::VectorXd> p = finiteNumbers(points[i], 3, problem);
    if (!p) f.failAt("points[" + std::to_string(i) + "]", problem);
    out.row(static_cast<Eigen::Index>(i)) = p->transpose();
  }
  return out;
}

/// Which member of a depth_image obstacle holds its image: exactly one of
/// `file` (beside the scene file) or, inline in base64 (a plan request's
/// obstacles), `png_base64` or `npy_base64`.
const char* imageKey(const Fields& f) {
  const char* key = nullptr;
  int given = 0;
  for (const char* k : {"file", "png_base64", "npy_base64"})
    if (f.has(k)) {
      key = k;
      ++given;
    }
  if (given != 1) f.fail("needs exactly one of file, png_base64 and npy_base64");
  return key;
}

/// The depth image in `key` (imageKey), times `scale` to metres.
DepthImage depthImage(const Fields& f, const std::string& key, const std::filesystem::path& baseDir,
                      double scale) {
  if (key == "file") return readDepthImage(baseDir / f.string("file"), scale);
  const std::string bytes = core::base64Decode(f.string(key.c_str()), key);
  return key == "png_base64" ? decodeDepthPng(bytes, scale, key)
                             : decodeDepthNpy(bytes, scale, key);
}

/// What a depth_image obstacle gives: its camera, image and mask (empty
/// when it has none).
struct SensedImage {
  DepthCamera camera;
  DepthImage image;
  std::vector<std::uint8_t> mask;
  const char* key = nullptr;  ///< the member that held the image
};

SensedImage sensedImage(const Fields& f, const std::filesystem::path& baseDir,
                        const std::string& where, const std::string& source) {
  SensedImage out;
  const std::string units = f.string("units");
  if (units != "m" && units != "mm") f.failAt("units", "must be m or mm, got '" + units + "'");
  const Fields k(f.at("intrinsics"), pathOf(where, "intrinsics"), source);
  out.camera.fx = k.positive("fx");
  out.camera.fy = k.positive("fy");
  out.camera.cx = k.number("cx");
  out.camera.cy = k.number("cy");
  out.camera.min_depth = f.nonNegative("min_depth", out.camera.min_depth);
  out.camera.max_depth = f.has("max_depth") ? f.positive("max_depth") : out.camera.max_depth;
  out.key = imageKey(f);
  out.image = depthImage(f, out.key, baseDir, units == "mm" ? 0.001 : 1.0);
  if (f.has("mask") && f.has("mask_base64")) f.fail("needs at most one of mask and mask_base64");
  if (f.has("mask")) out.mask = readMask(baseDir / f.string("mask"));
  if (f.has("mask_base64"))
    out.mask =
        decodeMaskPng(core::base64Decode(f.string("mask_base64"), "mask_base64"), "mask_base64");
  return out;
}

/// A points or depth_image obstacle's points, in its frame.
Vertices sensedPoints(const Fields& f, const std::string& type, const json& item,
                      const std::filesystem::path& baseDir, const std::string& where,
                      const std::string& source) {
  if (type == "points") {
    if (f.has("points") == f.has("file")) f.fail("needs either points or file");
    return f.has("points") ? inlinePoints(f, item.at("points"))
                           : readPointCloud(baseDir / f.string("file"));
  }
  const SensedImage sensed = sensedImage(f, baseDir, where, source);
  const bool masked = f.has("mask") || f.has("mask_base64");
  Vertices points = depthToPoints(sensed.image, sensed.camera, masked ? &sensed.mask : nullptr);
  if (points.rows() == 0) f.failAt(sensed.key, "has no depth within [min_depth, max_depth]");
  return points;
}

Obstacle parseObstacle(const json& item, std::size_t index, const std::filesystem::path& baseDir,
                       const std::string& source) {
  const Fields f(item, "obstacles[" + std::to_string(index) + "]", source);
  Obstacle o;
  o.name = f.string("name");
  if (o.name.empty()) f.failAt("name", "must not be empty");
  o.pose = f.pose("pose");
  const std::string type = f.string("type");
  if (type == "box") {
    o.type = Obstacle::Type::kBox;
    o.size = f.numbers("size", 3);
    if ((o.size.array() <= 0).any()) f.failAt("size", "must be positive");
  } else if (type == "cylinder") {
    o.type = Obstacle::Type::kCylinder;
    // Read before the comma initialiser: one that a throw leaves unfinished
    // fails Eigen's assertion in its destructor.
    const double radius = f.positive("radius");
    o.size = Eigen::Vector3d(radius, f.positive("length"), 0.0);
  } else if (type == "sphere") {
    o.type = Obstacle::Type::kSphere;
    o.size = Eigen::Vector3d(f.positive("radius"), 0.0, 0.0);
  } else if (type == "mesh") {
    o.type = Obstacle::Type::kMesh;
    const double scale = f.has("scale") ? f.positive("scale") : 1.0;
    try {
      LoadedMesh loaded = loadMesh(baseDir / f.string("mesh"), scale);
      o.mesh = std::move(loaded.mesh);
      o.distance_grid = std::make_shared<const db::DistanceGrid>(
          db::buildDistanceGrid(o.mesh, loaded.topology.closed()));
    } catch (const MeshError& e) {
      f.failAt("mesh", e.what());
    }
  } else if (type == "points" || type == "depth_image") {
    o.type = Obstacle::Type::kPoints;
    const std::string where = "obstacles[" + std::to_string(index) + "]";
    try {
      auto cloud =
          std::make_shared<VoxelCloud>(voxelize(sensedPoints(f, type, item, baseDir, where, source),
                                                cloudOptions(f, type, where, source, item)));
      o.mesh = cloud->mesh;
      o.distance_grid =
          std::shared_ptr<const db::DistanceGrid>(cloud, &cloud->distances);  // shares the cloud
      o.cloud = std::move(cloud);
    } catch (const InvalidArgument& e) {
      f.failAt(e.field(), e.problem());
    }
  } else {
    f.failAt("type",
             "must be box, cylinder, sphere, mesh, points or depth_image, got '" + type + "'");
  }
  return o;
}

/// The obstacles of the array `obstacles` (the member "obstacles" of the
/// source), their names unique.
std::vector<Obstacle> parseObstacleArray(const json& obstacles,
                                         const std::filesystem::path& baseDir,
                                         const std::string& source) {
  if (!obstacles.is_array()) throw SceneError(source, "obstacles", "must be an array");
  std::vector<Obstacle> out;
  std::set<std::string> names;
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    out.push_back(parseObstacle(obstacles[i], i, baseDir, source));
    if (!names.insert(out.back().name).second)
      throw SceneError(source, "obstacles[" + std::to_string(i) + "].name",
                       "'" + out.back().name + "' is used by another obstacle");
  }
  return out;
}

json parseJson(const std::string& text, const std::string& source) {
  try {
    return json::parse(text);
  } catch (const json::exception& e) {
    throw SceneError(source, "", std::string("not valid JSON (") + e.what() + ")");
  }
}

/// A pose with an optional `rest_on` naming an obstacle of `scene`.
Placement parsePlacement(const Fields& f, const Scene& scene, std::string name) {
  Placement out;
  out.name = std::move(name);
  out.pose = f.pose("pose");
  if (f.has("rest_on")) {
    out.rest_on = f.string("rest_on");
    if (scene.obstacle(out.rest_on) == nullptr)
      f.failAt("rest_on", "names no obstacle of the scene: '" + out.rest_on + "'");
  }
  return out;
}

}  // namespace

std::optional<Eigen::VectorXd> Scene::startFor(const std::string& robot) const {
  const auto it = robot_starts.find(robot);
  if (it != robot_starts.end()) return it->second;
  return start;
}

const Obstacle* Scene::obstacle(const std::string& obstacleName) const {
  for (const Obstacle& o : obstacles)
    if (o.name == obstacleName) return &o;
  return nullptr;
}

Scene Scene::withPlacement(const std::string& placementName) const {
  if (placementName == "target") return *this;
  for (const Placement& p : placements) {
    if (p.name != placementName) continue;
    Scene out = *this;
    out.target_pose = p.pose;
    out.target_rest_on = p.rest_on;
    return out;
  }
  std::string known = "target";
  for (const Placement& p : placements) known += ", " + p.name;
  throw SceneError("scene '" + name + "'", "placements",
                   "no placement '" + placementName + "' (known: " + known + ")");
}

double topOf(const Obstacle& o) {
  const Eigen::Matrix3d& r = o.pose.linear();
  const double z = o.pose.translation().z();
  switch (o.type) {
    case Obstacle::Type::kBox:  // the highest corner: half extents along each axis
      return z + 0.5 * (r.row(2).cwiseAbs().dot(o.size));
    case Obstacle::Type::kCylinder: {  // a cap's rim: the axis end plus the radius sideways
      const double axisZ = std::abs(r(2, 2));
      return z + 0.5 * o.size(1) * axisZ +
             o.size(0) * std::sqrt(std::max(0.0, 1.0 - axisZ * axisZ));
    }
    case Obstacle::Type::kSphere:
      return z + o.size(0);
    case Obstacle::Type::kMesh:
    case Obstacle::Type::kPoints:  // its voxels' boxes
      break;
  }
  double top = -std::numeric_limits<double>::infinity();
  for (Eigen::Index v = 0; v < o.mesh.vertices.rows(); ++v)
    top = std::max(top, (o.pose * o.mesh.vertices.row(v).transpose()).z());
  return top;
}

Eigen::Isometry3d restingPose(const Eigen::Isometry3d& pose, const Vertices& vertices,
                              const Obstacle& support) {
  if (vertices.rows() == 0) return pose;
  // The lowest vertex of the object turned as `pose` turns it.
  const double lowest = (vertices * pose.linear().row(2).transpose()).minCoeff();
  Eigen::Isometry3d out = pose;
  out.translation().z() = topOf(support) + kRestingClearance - lowest;
  return out;
}

Eigen::Isometry3d targetPose(const Scene& scene, const Vertices& vertices) {
  if (scene.target_rest_on.empty()) return scene.target_pose;
  const Obstacle* support = scene.obstacle(scene.target_rest_on);
  if (support == nullptr)
    throw SceneError("scene '" + scene.name + "'", "target.rest_on",
                     "names no obstacle of the scene: '" + scene.target_rest_on + "'");
  return restingPose(scene.target_pose, vertices, *support);
}

SceneError::SceneError(const std::string& source, std::string field, std::string problem)
    : std::runtime_error(source + ": " + (field.empty() ? "" : field + ": ") + problem),
      field_(std::move(field)),
      problem_(std::move(problem)) {}

bool isSafeName(const std::string& name) {
  if (name.empty() || name.size() > 128 || name[0] == '.') return false;
  for (const char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.')
      return false;
  return true;
}

Scene parseScene(const std::string& text, const std::filesystem::path& baseDir,
                 const std::string& what) {
  const json root = parseJson(text, what);
  const Fields f(root, "", what);
  Scene scene;
  scene.name = f.string("name");
  if (!isSafeName(scene.name)) f.failAt("name", "must be a simple name (letters, digits, _ - .)");
  if (f.has("description")) scene.description = f.string("description");
  scene.robot_base = f.pose("robot_base");
  scene.obstacles = parseObstacleArray(f.at("obstacles"), baseDir, what);
  const Fields target(f.at("target"), "target", what);
  scene.target_object = target.string("object");
  if (!isSafeName(scene.target_object))
    target.failAt("object", "must be a database name without path characters");
  const Placement own = parsePlacement(target, scene, "target");
  scene.target_pose = own.pose;
  scene.target_rest_on = own.rest_on;
  if (f.has("placements")) {
    const json& placements = f.at("placements");
    if (!placements.is_array()) f.failAt("placements", "must be an array");
    std::set<std::string> placementNames{"target"};
    for (std::size_t i = 0; i < placements.size(); ++i) {
      const Fields p(placements[i], "placements[" + std::to_string(i) + "]", what);
      const std::string name = p.string("name");
      if (!isSafeName(name)) p.failAt("name", "must be a simple name (letters, digits, _ - .)");
      if (!placementNames.insert(name).second) p.failAt("name", "'" + name + "' is used twice");
      scene.placements.push_back(parsePlacement(p, scene, name));
    }
  }
  if (f.has("start")) {
    if (f.at("start").is_object()) {  // per robot: {"<robot name>": [...], ...}
      const Fields starts(f.at("start"), "start", what);
      for (const auto& item : f.at("start").items()) {
        if (!isSafeName(item.key())) starts.failAt(item.key(), "must be a robot name");
        scene.robot_starts.emplace(item.key(), starts.numbers(item.key().c_str(), -1));
      }
    } else {
      scene.start = f.numbers("start", -1);
    }
  }
  return scene;
}

std::vector<Obstacle> parseObstacles(const std::string& text, const std::filesystem::path& baseDir,
                                     const std::string& what) {
  return parseObstacleArray(parseJson(text, what), baseDir, what);
}

std::vector<TargetView> loadTargetViews(const std::filesystem::path& path) {
  const std::string what = "scene '" + path.string() + "'";
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(what, "", "cannot read the file");
  std::ostringstream text;
  text << in.rdbuf();
  const json root = parseJson(text.str(), what);
  const Fields f(root, "", what);
  const json& obstacles = f.at("obstacles");
  if (!obstacles.is_array()) f.failAt("obstacles", "must be an array");
  std::vector<TargetView> out;
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    const std::string where = "obstacles[" + std::to_string(i) + "]";
    const Fields o(obstacles[i], where, what);
    if (o.string("type") != "depth_image" || !(o.has("mask") || o.has("mask_base64"))) continue;
    TargetView& view = out.emplace_back();
    view.name = o.string("name");
    view.pose = o.pose("pose");
    try {
      SensedImage sensed = sensedImage(o, path.parent_path(), where, what);
      // Checks the camera and the sizes as the obstacle's reading would.
      depthToPoints(sensed.image, sensed.camera, &sensed.mask);
      for (float& depth : sensed.image.depths)
        if (!(static_cast<double>(depth) >= sensed.camera.min_depth &&
              static_cast<double>(depth) <= sensed.camera.max_depth))
          depth = 0.0f;
      view.camera = sensed.camera;
      view.image = std::move(sensed.image);
      view.mask = std::move(sensed.mask);
    } catch (const InvalidArgument& e) {
      o.failAt(e.field(), e.problem());
    }
  }
  if (out.empty())
    throw SceneError(what, "obstacles", "has no depth_image with a mask (the target's pixels)");
  return out;
}

Scene loadScene(const std::filesystem::path& path) {
  const std::string what = "scene '" + path.string() + "'";
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(what, "", "cannot read the file");
  std::ostringstream text;
  text << in.rdbuf();
  return parseScene(text.str(), path.parent_path(), what);
}

}  // namespace hfts::robot
