#include "fcl_query.h"

#include <fcl/geometry/octree/octree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <utility>

namespace hfts::robot::fcl_query {

Geometry primitive(int type, const Eigen::Vector3d& size) {
  switch (type) {
    case 0:
      return std::make_shared<fcl::Boxd>(size.x(), size.y(), size.z());
    case 1:
      return std::make_shared<fcl::Cylinderd>(size.x(), size.y());
    default:
      return std::make_shared<fcl::Sphered>(size.x());
  }
}

Vertices cloudCorners(const VoxelCloud& cloud) {
  Vertices corners(2, 3);
  corners.row(0) = cloud.low().transpose();
  corners.row(1) = cloud.high().transpose();
  return corners;
}

Geometry cloudGeometry(const VoxelCloud& cloud) {
  // Voxel i of the cloud spans [i v, (i + 1) v): octomap's key i + 2^15 at
  // depth 16, whose box FCL computes the same way.
  auto tree = std::make_shared<octomap::OcTree>(cloud.options.voxel);
  const int offset = tree->coordToKey(0.0);  // octomap's tree_max_val
  for (int z = 0; z < cloud.dims[2]; ++z)
    for (int y = 0; y < cloud.dims[1]; ++y)
      for (int x = 0; x < cloud.dims[0]; ++x) {
        const int i = cloud.first[0] + x, j = cloud.first[1] + y, k = cloud.first[2] + z;
        if (!cloud.isOccupied(i, j, k)) continue;
        const octomap::OcTreeKey key(static_cast<octomap::key_type>(i + offset),
                                     static_cast<octomap::key_type>(j + offset),
                                     static_cast<octomap::key_type>(k + offset));
        tree->updateNode(key, tree->getClampingThresMaxLog());
      }
  return std::make_shared<fcl::OcTreed>(std::move(tree));
}

Geometry meshGeometry(const TriangleMesh& mesh) {
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Vector3d> points;
  std::vector<fcl::Triangle> triangles;
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) points.emplace_back(mesh.vertices.row(v));
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    triangles.emplace_back(mesh.triangles(t, 0), mesh.triangles(t, 1), mesh.triangles(t, 2));
  model->beginModel();
  model->addSubModel(points, triangles);
  model->endModel();
  return model;
}

namespace {

bool ignored(const Tag& a, const Tag& b, const QueryData& data) {
  if (a.link >= 0 && b.link >= 0)
    return !data.self || a.link == b.link || data.model->isCollisionDisabled(a.link, b.link);
  if (!data.target && (a.target || b.target)) return true;
  if (!data.obstacles && ((a.link < 0 && !a.target) || (b.link < 0 && !b.target))) return true;
  return a.link < 0 && b.link < 0;  // environment against itself
}

/// Tolerance of the depth of a fingertip shape in the target (m): the
/// depth is bounded from above, never underestimated.
constexpr double kDepthTolerance = 2e-5;

/// Under the grasp rule: whether a fingertip shape that FCL finds touching
/// the target stays within the allowed depth (then it is no collision).
bool withinAllowedDepth(const Object& shape, const Tag& tag, const GraspContactRule& rule) {
  if (rule.surface == nullptr || tag.primitive_type < 0) return false;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = shape.getRotation();
  pose.translation() = shape.getTranslation();
  CollisionShape primitive;
  primitive.type = static_cast<CollisionShape::Type>(tag.primitive_type);
  primitive.size = tag.primitive_size;
  const double allowed = -rule.maxPenetration;
  return rule.surface
             ->shapeDistance(primitive, rule.worldToObject * pose, kDepthTolerance, allowed,
                             allowed)
             .lower >= allowed;
}

}  // namespace

bool collideCallback(Object* o1, Object* o2, void* raw) {
  auto* data = static_cast<QueryData*>(raw);
  if (static_cast<const Tag*>(o1->getUserData())->order >
      static_cast<const Tag*>(o2->getUserData())->order)
    std::swap(o1, o2);
  const Tag& a = *static_cast<const Tag*>(o1->getUserData());
  const Tag& b = *static_cast<const Tag*>(o2->getUserData());
  if (ignored(a, b, *data)) return false;
  if (data->clearance > 0.0) {
    fcl::DistanceRequestd request;
    fcl::DistanceResultd result;
    if (fcl::distance(o1, o2, request, result) >= data->clearance) return false;
  } else {
    fcl::CollisionRequestd request;
    fcl::CollisionResultd result;
    if (fcl::collide(o1, o2, request, result) == 0) return false;
  }
  if (data->allowFingertipContact && (a.target || b.target) && (a.fingertip || b.fingertip)) {
    const bool robotFirst = a.fingertip;
    if (withinAllowedDepth(robotFirst ? *o1 : *o2, robotFirst ? a : b, data->rule)) return false;
  }
  data->collision = true;
  data->pair = a.link < 0 ? CollisionPair{b.name, a.name} : CollisionPair{a.name, b.name};
  return true;  // stop at the first contact (the robot's part named first)
}

bool distanceCallback(Object* o1, Object* o2, void* raw, double& minimum) {
  auto* data = static_cast<QueryData*>(raw);
  const Tag& a = *static_cast<const Tag*>(o1->getUserData());
  const Tag& b = *static_cast<const Tag*>(o2->getUserData());
  if (a.link < 0 || ignored(a, b, *data)) {
    minimum = data->distance;
    return false;
  }
  fcl::DistanceRequestd request;
  fcl::DistanceResultd result;
  // A mesh far enough away: its bounding box's distance will do (o1 is
  // the robot's here).
  if (data->exactWithin > 0.0 && b.link < 0 && b.bound != nullptr) {
    fcl::distance(o1, b.bound, request, result);
    if (result.min_distance >= data->exactWithin) {
      data->distance = std::min(data->distance, result.min_distance);
      minimum = data->distance;
      return false;
    }
    result.clear();
  }
  fcl::distance(o1, o2, request, result);
  data->distance = std::min(data->distance, std::max(0.0, result.min_distance));
  minimum = data->distance;
  return data->distance <= 0.0;
}

bool objectDistanceCallback(Object* o1, Object* o2, void* raw, double& minimum) {
  if (static_cast<const Tag*>(o1->getUserData())->link < 0) std::swap(o1, o2);
  return distanceCallback(o1, o2, raw, minimum);
}

bool targetCallback(Object* o1, Object* o2, void* raw) {
  const Tag& a = *static_cast<const Tag*>(o1->getUserData());
  const Tag& b = *static_cast<const Tag*>(o2->getUserData());
  if (a.target == b.target || a.beside_target || b.beside_target) return false;
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  if (fcl::collide(o1, o2, request, result) == 0) return false;
  auto* data = static_cast<QueryData*>(raw);
  data->collision = true;
  data->pair = {a.name, b.name};
  return true;
}

/// One object (QueryData::query) against the environment: any collision
/// except with the target object; the pair names the object first.
bool obstacleCallback(Object* o1, Object* o2, void* raw) {
  auto* data = static_cast<QueryData*>(raw);
  if (o2->getUserData() == data->query) std::swap(o1, o2);
  const Tag& a = *static_cast<const Tag*>(o1->getUserData());
  const Tag& b = *static_cast<const Tag*>(o2->getUserData());
  if (a.target || b.target) return false;
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  if (fcl::collide(o1, o2, request, result) == 0) return false;
  data->collision = true;
  data->pair = {a.name, b.name};
  return true;
}

/// The environment as the sphere tier sees it, in the scene's order:
/// obstacles, then the target. A mesh becomes its bounding box, refined by
/// its distance grid when it has one.
std::vector<SphereTier::Item> sphereTierItems(const Scene& scene,
                                              const db::ObjectGeometry* target) {
  std::vector<SphereTier::Item> items;
  auto add = [&](int type, const Eigen::Vector3d& size, const Eigen::Isometry3d& pose,
                 bool isTarget) {
    items.push_back(
        {static_cast<CollisionShape::Type>(type), size, pose.inverse(), isTarget, std::nullopt});
  };
  auto addMesh = [&](const Vertices& vertices, const db::DistanceGrid* grid,
                     const Eigen::Isometry3d& pose, bool isTarget) {
    const Eigen::Vector3d low = vertices.colwise().minCoeff(), high = vertices.colwise().maxCoeff();
    const Eigen::Vector3d center = (low + high) / 2;
    add(static_cast<int>(CollisionShape::Type::kBox), high - low,
        pose * Eigen::Translation3d(center), isTarget);
    if (grid == nullptr || grid->empty()) return;
    items.back().grid =
        SphereTier::Grid{grid->values.data(),
                         grid->origin - center,
                         grid->spacing,
                         {static_cast<int>(grid->dims[0]), static_cast<int>(grid->dims[1]),
                          static_cast<int>(grid->dims[2])}};
  };
  for (const Obstacle& o : scene.obstacles) {
    if (o.type == Obstacle::Type::kMesh)
      addMesh(o.mesh.vertices, o.distance_grid.get(), o.pose, false);
    else if (o.type == Obstacle::Type::kPoints)
      addMesh(cloudCorners(*o.cloud), &o.cloud->distances, o.pose, false);
    else
      add(static_cast<int>(o.type), o.size, o.pose, false);
  }
  // The target outlives the scene (the constructor's contract), so the
  // tier reads its grid in place.
  if (target != nullptr)
    addMesh(target->mesh_vertices, &target->distance_grid, scene.target_pose, true);
  return items;
}

}  // namespace hfts::robot::fcl_query
