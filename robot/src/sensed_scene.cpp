#include "robot/sensed_scene.h"

#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <unordered_set>

#include "core/invalid_argument.h"
#include "fcl_query.h"
#include "robot/kinematics.h"

namespace hfts::robot {
namespace {

/// `scene` with each cloud obstacle's voxels that `remove(obstacle, i, j,
/// k)` names taken out (a cloud left empty goes); untouched clouds shared.
Scene carved(const Scene& scene,
             const std::function<bool(const Obstacle&, int, int, int)>& remove) {
  if (std::none_of(scene.obstacles.begin(), scene.obstacles.end(),
                   [](const Obstacle& o) { return o.type == Obstacle::Type::kPoints; }))
    return scene;
  Scene out = scene;
  for (Obstacle& o : out.obstacles) {
    if (o.type != Obstacle::Type::kPoints) continue;
    VoxelCloud kept =
        withoutVoxels(*o.cloud, [&](int i, int j, int k) { return remove(o, i, j, k); });
    if (kept.occupied_count == o.cloud->occupied_count) continue;
    auto cloud = std::make_shared<const VoxelCloud>(std::move(kept));
    o.mesh = cloud->mesh;
    o.distance_grid = std::shared_ptr<const db::DistanceGrid>(cloud, &cloud->distances);
    o.cloud = std::move(cloud);
  }
  out.obstacles.erase(std::remove_if(out.obstacles.begin(), out.obstacles.end(),
                                     [](const Obstacle& o) {
                                       return o.type == Obstacle::Type::kPoints &&
                                              o.cloud->occupied_count == 0;
                                     }),
                      out.obstacles.end());
  return out;
}

Eigen::Vector3d voxelCentre(const Obstacle& o, int i, int j, int k) {
  return Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5) * o.cloud->options.voxel;
}

}  // namespace

namespace {

/// A voxel's absolute index as one key (kMaxVoxelIndex bounds each).
std::uint64_t voxelKey(int i, int j, int k) {
  const auto part = [](int x) { return static_cast<std::uint64_t>(x + (1 << 20)) & 0x1fffff; };
  return (part(i) << 42) | (part(j) << 21) | part(k);
}

std::array<int, 3> voxelOf(const Eigen::Vector3d& p, double voxel) {
  return {static_cast<int>(std::floor(p.x() / voxel)), static_cast<int>(std::floor(p.y() / voxel)),
          static_cast<int>(std::floor(p.z() / voxel))};
}

/// The occupied voxels of `target` (its frame) that `viewer`'s camera saw
/// through: along the ray to each of its points, up to the point less its
/// radius and half of target's voxel diagonal.
void appendSeenThrough(const Obstacle& target, const Obstacle& viewer,
                       std::unordered_set<std::uint64_t>& seen) {
  const VoxelCloud& to = *target.cloud;
  const VoxelCloud& from = *viewer.cloud;
  const double v = to.options.voxel;
  const Eigen::Isometry3d toTarget = target.pose.inverse() * viewer.pose;
  const Eigen::Vector3d eye = toTarget * *from.options.viewpoint;
  const double margin = from.options.radius + 0.5 * std::sqrt(3.0) * v;
  for (Eigen::Index p = 0; p < from.points.rows(); ++p) {
    const Eigen::Vector3d point = toTarget * Eigen::Vector3d(from.points.row(p).transpose());
    const Eigen::Vector3d ray = point - eye;
    const double length = ray.norm() - margin;
    if (!(length > 0.0)) continue;
    const Eigen::Vector3d along = ray.normalized();
    for (double t = 0.0; t < length; t += v / 2) {
      const auto [i, j, k] = voxelOf(eye + t * along, v);
      if (to.isOccupied(i, j, k)) seen.insert(voxelKey(i, j, k));
    }
  }
}

/// The voxels of `cloud` within its radius of one of its own points.
std::unordered_set<std::uint64_t> observedVoxels(const VoxelCloud& cloud) {
  std::unordered_set<std::uint64_t> out;
  const double v = cloud.options.voxel, r = cloud.options.radius;
  for (Eigen::Index p = 0; p < cloud.points.rows(); ++p) {
    const Eigen::Vector3d point = cloud.points.row(p).transpose();
    const auto from = voxelOf(point - Eigen::Vector3d::Constant(r), v);
    const auto to = voxelOf(point + Eigen::Vector3d::Constant(r), v);
    for (int k = from[2]; k <= to[2]; ++k)
      for (int j = from[1]; j <= to[1]; ++j)
        for (int i = from[0]; i <= to[0]; ++i) {
          const Eigen::Vector3d low = Eigen::Vector3d(i, j, k) * v;
          const Eigen::Vector3d gap =
              (low - point).cwiseMax(point - low - Eigen::Vector3d::Constant(v)).cwiseMax(0.0);
          if (gap.squaredNorm() <= r * r) out.insert(voxelKey(i, j, k));
        }
  }
  return out;
}

}  // namespace

Scene withSeenSpaceCarved(const Scene& scene) {
  std::vector<const Obstacle*> views;
  for (const Obstacle& o : scene.obstacles)
    if (o.type == Obstacle::Type::kPoints && o.cloud->options.viewpoint &&
        o.cloud->points.rows() > 0)
      views.push_back(&o);
  if (views.size() < 2) return scene;
  std::map<std::string, std::unordered_set<std::uint64_t>> carve;
  for (const Obstacle* target : views) {
    std::unordered_set<std::uint64_t> seen;
    for (const Obstacle* viewer : views)
      if (viewer != target) appendSeenThrough(*target, *viewer, seen);
    for (const std::uint64_t key : observedVoxels(*target->cloud)) seen.erase(key);
    carve[target->name] = std::move(seen);
  }
  return carved(scene, [&](const Obstacle& o, int i, int j, int k) {
    const auto found = carve.find(o.name);
    return found != carve.end() && found->second.count(voxelKey(i, j, k)) > 0;
  });
}

namespace {

/// Whether a voxel of edge `voxel` centred at `centre` (the object's
/// frame) may touch the object of `grid` and `vertices`: the grid cannot
/// prove the centre more than half the voxel's diagonal outside it.
bool mayTouchObject(const db::DistanceGrid& grid, const Vertices& vertices,
                    const Eigen::Vector3d& centre, double voxel) {
  const double halfDiagonal = 0.5 * std::sqrt(3.0) * voxel;
  // Outside the object's box by more than the half diagonal: clear.
  if ((centre.transpose().array() < vertices.colwise().minCoeff().array() - halfDiagonal).any() ||
      (centre.transpose().array() > vertices.colwise().maxCoeff().array() + halfDiagonal).any())
    return false;
  return grid.lowerBound(centre) <= halfDiagonal;
}

}  // namespace

Scene withTargetCarved(const Scene& scene, const db::DistanceGrid& grid, const Vertices& vertices) {
  if (vertices.rows() == 0 || grid.empty()) return scene;
  return carved(scene, [&](const Obstacle& o, int i, int j, int k) {
    return mayTouchObject(grid, vertices,
                          scene.target_pose.inverse() * o.pose * voxelCentre(o, i, j, k),
                          o.cloud->options.voxel);
  });
}

std::string hiddenSideName(const std::string& target) {
  return target + ".hidden";
}

std::string hiddenSkinName(const std::string& target) {
  return target + ".hidden_skin";
}

namespace {

/// An obstacle of the voxels of edge `voxel` centred at `centres` (the
/// target's frame, at `pose`): exactly those voxels, no radius.
Obstacle hiddenVoxels(const std::string& name, const std::vector<Eigen::Vector3d>& centres,
                      double voxel, const Eigen::Isometry3d& pose) {
  Vertices points(static_cast<Eigen::Index>(centres.size()), 3);
  for (std::size_t i = 0; i < centres.size(); ++i)
    points.row(static_cast<Eigen::Index>(i)) = centres[i].transpose();
  CloudOptions options;
  options.voxel = voxel;
  options.radius = 0.0;
  options.shadow = 0.0;
  Obstacle o;
  o.name = name;
  o.type = Obstacle::Type::kPoints;
  o.pose = pose;
  try {
    auto cloud = std::make_shared<VoxelCloud>(voxelize(points, options));
    o.mesh = cloud->mesh;
    o.distance_grid = std::shared_ptr<const db::DistanceGrid>(cloud, &cloud->distances);
    o.cloud = std::move(cloud);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument("partial_view", "the hidden space of '" + name + "': " + e.problem());
  }
  return o;
}

}  // namespace

Scene withHiddenSide(const Scene& scene, const db::ObjectDatabase& target) {
  if (!target.partial_view || target.partial_view->hidden_low.rows() == 0) return scene;
  const db::PartialView& view = *target.partial_view;
  const db::ObjectGeometry& geometry = target.geometry;
  const bool split = !geometry.distance_grid.empty() && geometry.mesh_vertices.rows() > 0;
  // The centre of every voxel of every box: a cloud of the same voxel and
  // no radius holds exactly the boxes.
  const double v = view.hidden_voxel;
  std::vector<Eigen::Vector3d> apart, skin;
  for (Eigen::Index b = 0; b < view.hidden_low.rows(); ++b) {
    const Eigen::Array3d first = (view.hidden_low.row(b).transpose().array() / v).round();
    const Eigen::Array3d end = (view.hidden_high.row(b).transpose().array() / v).round();
    for (double k = first.z(); k < end.z(); ++k)
      for (double j = first.y(); j < end.y(); ++j)
        for (double i = first.x(); i < end.x(); ++i) {
          const Eigen::Vector3d centre(v * (i + 0.5), v * (j + 0.5), v * (k + 0.5));
          const bool touches =
              split && mayTouchObject(geometry.distance_grid, geometry.mesh_vertices, centre, v);
          (touches ? skin : apart).push_back(centre);
        }
  }
  Scene out = scene;
  for (const auto& [name, centres] : {std::pair{hiddenSideName(scene.target_object), &apart},
                                      std::pair{hiddenSkinName(scene.target_object), &skin}})
    if (!centres->empty())
      out.obstacles.push_back(hiddenVoxels(name, *centres, v, scene.target_pose));
  return out;
}

Scene heldScene(Scene scene) {
  const std::string skin = hiddenSkinName(scene.target_object);
  scene.obstacles.erase(std::remove_if(scene.obstacles.begin(), scene.obstacles.end(),
                                       [&](const Obstacle& o) { return o.name == skin; }),
                        scene.obstacles.end());
  scene.target_object.clear();
  return scene;
}

Scene withRobotCarved(const Scene& scene, const RobotModel& model, const Eigen::VectorXd& q,
                      double padding) {
  if (std::none_of(scene.obstacles.begin(), scene.obstacles.end(),
                   [](const Obstacle& o) { return o.type == Obstacle::Type::kPoints; }))
    return scene;
  const LinkPoses poses = forwardKinematics(model, q);
  struct Shape {
    fcl_query::Object object;
    Eigen::AlignedBox3d box;  ///< world frame, FCL's
  };
  std::vector<Shape> shapes;
  for (std::size_t l = 0; l < model.links().size(); ++l)
    for (const CollisionShape& s : model.links()[l].shapes) {
      const Eigen::Isometry3d pose = scene.robot_base * poses[l] * s.origin;
      fcl_query::Object object(fcl_query::primitive(static_cast<int>(s.type), s.size),
                               pose.linear(), pose.translation());
      object.computeAABB();
      shapes.push_back({object, Eigen::AlignedBox3d(object.getAABB().min_, object.getAABB().max_)});
    }
  return carved(scene, [&](const Obstacle& o, int i, int j, int k) {
    const double reach = padding + 0.5 * std::sqrt(3.0) * o.cloud->options.voxel;
    const Eigen::Vector3d centre = o.pose * voxelCentre(o, i, j, k);
    for (const Shape& s : shapes) {
      if (s.box.exteriorDistance(centre) > reach) continue;
      fcl_query::Object point(std::make_shared<fcl::Sphered>(1e-9), Eigen::Matrix3d::Identity(),
                              centre);
      fcl::DistanceRequestd request;
      fcl::DistanceResultd result;
      if (fcl::distance(&s.object, &point, request, result) <= reach) return true;
    }
    return false;
  });
}

Scene asPlannerSees(const Scene& scene, const db::ObjectDatabase& target, const RobotModel& model,
                    const Eigen::VectorXd& start) {
  Scene s = withSeenSpaceCarved(scene);
  s = withTargetCarved(s, target.geometry.distance_grid, target.geometry.mesh_vertices);
  s = withHiddenSide(s, target);
  return withRobotCarved(s, model, start);
}

}  // namespace hfts::robot
