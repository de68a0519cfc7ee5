#include "robot/sensed_scene.h"

#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>

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

Scene withTargetCarved(const Scene& scene, const db::DistanceGrid& grid, const Vertices& vertices) {
  if (vertices.rows() == 0 || grid.empty()) return scene;
  const Eigen::Vector3d low = vertices.colwise().minCoeff(), high = vertices.colwise().maxCoeff();
  return carved(scene, [&](const Obstacle& o, int i, int j, int k) {
    const double halfDiagonal = 0.5 * std::sqrt(3.0) * o.cloud->options.voxel;
    const Eigen::Vector3d centre = scene.target_pose.inverse() * o.pose * voxelCentre(o, i, j, k);
    // Outside the object's box by more than the half diagonal: clear.
    if ((centre.array() < low.array() - halfDiagonal).any() ||
        (centre.array() > high.array() + halfDiagonal).any())
      return false;
    return grid.lowerBound(centre) <= halfDiagonal;
  });
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

}  // namespace hfts::robot
