// CollisionScene (collision_checker.h): one robot in one scene, built
// once and read by every checker over it; CollisionMesh, a mesh's FCL
// hierarchy built once per object.
#include "collision_scene.h"

#include <fcl/narrowphase/collision.h>

#include <cmath>
#include <string>

#include "core/invalid_argument.h"
#include "robot/sensed_scene.h"

namespace hfts::robot {

using fcl_query::cloudCorners;
using fcl_query::cloudGeometry;
using fcl_query::meshGeometry;
using fcl_query::obstacleCallback;
using fcl_query::primitive;
using fcl_query::QueryData;
using fcl_query::sphereTierItems;
using fcl_query::targetCallback;

struct CollisionMesh::Impl {
  Geometry geometry;
  /// Making a collision object of a geometry writes the geometry's local
  /// bounding box (the same values every time) and placing the object
  /// reads it: one checker at a time. Queries do not touch it.
  std::mutex objectCreation;
};

CollisionMesh::CollisionMesh(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  impl_->geometry = meshGeometry(mesh);
}

CollisionMesh::~CollisionMesh() = default;

namespace {

/// Whether two placed objects touch: FCL's narrowphase where their
/// bounding boxes (conservative, touching included) overlap.
bool touch(const Object& a, const Object& b) {
  if (!a.getAABB().overlap(b.getAABB())) return false;
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  return fcl::collide(&a, &b, request, result) > 0;
}

}  // namespace

void CollisionScene::Impl::addSphereTier(std::vector<SphereTier::Item> items) {
  const RobotModel& robot = model.robot;
  tier = std::make_unique<SphereTier>(model, scene.robot_base, items);
  // The static links' shapes, once, where they stand.
  RobotObjects at(robot, tags.size(), [this](int link) { return tier->isStatic(link); });
  LinkPoses poses;
  forwardKinematics(robot, robot.home(), poses);
  at.place(scene.robot_base, poses);
  const std::size_t links = robot.links().size();
  // staticTouching[link][e]: a shape of the static link touches environment
  // object e; linksTouching[a][b]: shapes of two static links touch.
  std::vector<std::vector<bool>> staticTouching(links,
                                                std::vector<bool>(environmentObjects.size()));
  std::vector<std::vector<bool>> linksTouching(links, std::vector<bool>(links));
  for (std::size_t i = 0; i < at.objects.size(); ++i) {
    const auto link = static_cast<std::size_t>(at.shapes[i].first);
    for (std::size_t e = 0; e < environmentObjects.size(); ++e)
      if (touch(*at.objects[i], *environmentObjects[e])) staticTouching[link][e] = true;
    for (std::size_t j = 0; j < at.objects.size(); ++j) {
      const auto other = static_cast<std::size_t>(at.shapes[j].first);
      if (touch(*at.objects[i], *at.objects[j]))
        linksTouching[link][other] = linksTouching[other][link] = true;
    }
  }
  const auto skipClearStatic = [&](SphereTier& t) {
    for (std::size_t a = 0; a < links; ++a) {
      if (!t.isStatic(static_cast<int>(a))) continue;
      for (std::size_t e = 0; e < environmentObjects.size(); ++e)
        if (!staticTouching[a][e]) t.skipStatic(static_cast<int>(a), e);
      for (std::size_t b = a + 1; b < links; ++b)
        if (t.isStatic(static_cast<int>(b)) && !linksTouching[a][b])
          t.skipStaticPair(static_cast<int>(a), static_cast<int>(b));
    }
    t.listPairs();
  };
  skipClearStatic(*tier);
  if (clearance <= 0.0) return;
  // The same pairs grown by the clearance: a static link need only be free
  // (keepsClearance), so its pairs that FCL found clear stay dropped.
  clearanceTier =
      std::make_unique<SphereTier>(model, scene.robot_base, std::move(items), clearance);
  skipClearStatic(*clearanceTier);
}

CollisionScene::CollisionScene(const CollisionModel& model, const Scene& scene,
                               const db::ObjectGeometry* target, const CollisionMesh* targetMesh,
                               const ObjectSurface* targetSurface, double clearance)
    : impl_(std::isfinite(clearance) && clearance >= 0.0
                ? std::make_unique<Impl>(model, scene, clearance)
                : throw InvalidArgument("clearance", "must be a finite distance >= 0 (m), not " +
                                                         std::to_string(clearance))) {
  impl_->target = target;
  impl_->sharedSurface = target != nullptr ? targetSurface : nullptr;
  for (const Obstacle& o : scene.obstacles) {
    Tag tag{-1, false, false, "obstacle '" + o.name + "'"};
    tag.beside_target = isHiddenSpaceOf(o.name, scene.target_object);
    if (o.type == Obstacle::Type::kMesh) {
      impl_->addEnvironment(meshGeometry(o.mesh), o.pose, std::move(tag), nullptr, o.mesh.vertices);
    } else if (o.type == Obstacle::Type::kPoints) {
      impl_->addEnvironment(cloudGeometry(*o.cloud), o.pose, std::move(tag), nullptr,
                            cloudCorners(*o.cloud));
    } else {
      tag.primitive_type = static_cast<int>(o.type);
      tag.primitive_size = o.size;
      impl_->addEnvironment(primitive(static_cast<int>(o.type), o.size), o.pose, std::move(tag));
    }
  }
  if (target != nullptr) {
    Tag tag{-1, true, false, "target '" + scene.target_object + "'"};
    if (targetMesh != nullptr) {
      impl_->addEnvironment(targetMesh->impl_->geometry, scene.target_pose, std::move(tag),
                            &targetMesh->impl_->objectCreation, target->mesh_vertices);
    } else {
      const TriangleMesh mesh{target->mesh_vertices, target->mesh_triangles};
      impl_->addEnvironment(meshGeometry(mesh), scene.target_pose, std::move(tag), nullptr,
                            target->mesh_vertices);
    }
  }
  impl_->environment.setup();
  // The tier reads the obstacles' grids in the scene's copy, the target's
  // in the target's geometry (which outlives the scene).
  impl_->addSphereTier(sphereTierItems(impl_->scene, target));
}

CollisionScene::~CollisionScene() = default;

const CollisionModel& CollisionScene::model() const {
  return impl_->model;
}

const Scene& CollisionScene::scene() const {
  return impl_->scene;
}

double CollisionScene::clearance() const {
  return impl_->clearance;
}

bool CollisionScene::targetTouchesObstacles(CollisionPair* pair) const {
  QueryData data;
  impl_->environment.collide(&data, targetCallback);
  if (data.collision && pair != nullptr) *pair = data.pair;
  return data.collision;
}

bool CollisionScene::sphereTouchesObstacles(const Eigen::Vector3d& center, double radius,
                                            CollisionPair* pair) const {
  if (!(radius > 0.0) || !std::isfinite(radius) || !center.allFinite())
    throw InvalidArgument("sphere", "needs a finite centre and a radius > 0");
  Object sphere(std::make_shared<fcl::Sphered>(radius), Eigen::Matrix3d::Identity(), center);
  sphere.computeAABB();
  Tag tag{-1, false, false, "sphere"};
  sphere.setUserData(&tag);
  QueryData data;
  data.query = &tag;
  impl_->environment.collide(&sphere, &data, obstacleCallback);
  if (data.collision && pair != nullptr) *pair = data.pair;
  return data.collision;
}

}  // namespace hfts::robot
