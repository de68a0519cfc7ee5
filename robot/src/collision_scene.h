#pragma once
// The shared part of collision checking, private to the robot library:
// CollisionScene's implementation, which every CollisionChecker over the
// scene reads, and the robot's FCL objects (a checker's own; the scene's
// once while it decides which static pairs the sphere tier may skip).

#include <functional>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "fcl_query.h"
#include "robot/collision_checker.h"
#include "robot/kinematics.h"
#include "robot/object_surface.h"
#include "sphere_tier.h"

namespace hfts::robot {

using fcl_query::Geometry;
using fcl_query::Object;
using fcl_query::Tag;

/// The robot's FCL objects, one per collision shape of a link (and one
/// for a held body's mesh, RobotModel::withHeldBody): a
/// checker's own (queries move them), and the scene's once while it
/// decides which static pairs the tier may skip.
struct RobotObjects {
  std::vector<std::unique_ptr<Tag>> tags;
  std::vector<std::unique_ptr<Object>> objects;
  std::vector<std::pair<int, Eigen::Isometry3d>> shapes;  // link, shape origin
  std::vector<std::vector<std::size_t>> linkObjects;      // per link: its objects

  /// Tags are numbered from `firstOrder` on (after the environment's).
  /// With `only`, the shapes of the links it accepts alone.
  RobotObjects(const RobotModel& model, std::size_t firstOrder,
               const std::function<bool(int link)>& only = {}) {
    std::vector<bool> fingertip(model.links().size(), false);
    for (const Fingertip& f : model.fingertips())
      fingertip[static_cast<std::size_t>(f.link)] = true;
    for (std::size_t l = 0; l < model.links().size(); ++l) {
      if (only && !only(static_cast<int>(l))) continue;
      for (const CollisionShape& shape : model.links()[l].shapes) {
        auto object = std::make_unique<Object>(
            fcl_query::primitive(static_cast<int>(shape.type), shape.size));
        auto tag = std::make_unique<Tag>(
            Tag{static_cast<int>(l), false, fingertip[l], model.links()[l].name});
        tag->order = firstOrder + tags.size();
        tag->primitive_type = static_cast<int>(shape.type);
        tag->primitive_size = shape.size;
        object->setUserData(tag.get());
        tags.push_back(std::move(tag));
        objects.push_back(std::move(object));
        shapes.emplace_back(static_cast<int>(l), shape.origin);
      }
      if (const std::shared_ptr<const TriangleMesh>& mesh = model.links()[l].mesh) {
        // A held body: its mesh's hierarchy, made for this set of objects
        // (a few milliseconds per thousand triangles).
        auto object = std::make_unique<Object>(fcl_query::meshGeometry(*mesh));
        auto tag =
            std::make_unique<Tag>(Tag{static_cast<int>(l), false, false, model.links()[l].name});
        tag->order = firstOrder + tags.size();
        object->setUserData(tag.get());
        tags.push_back(std::move(tag));
        objects.push_back(std::move(object));
        shapes.emplace_back(static_cast<int>(l), Eigen::Isometry3d::Identity());
      }
    }
    linkObjects.resize(model.links().size());
    for (std::size_t i = 0; i < shapes.size(); ++i)
      linkObjects[static_cast<std::size_t>(shapes[i].first)].push_back(i);
  }

  /// Moves every object to its link's pose in `poses` (base frame).
  void place(const Eigen::Isometry3d& base, const LinkPoses& poses) {
    for (std::size_t i = 0; i < objects.size(); ++i) {
      const Eigen::Isometry3d pose =
          base * poses[static_cast<std::size_t>(shapes[i].first)] * shapes[i].second;
      objects[i]->setTransform(pose.linear(), pose.translation());
      objects[i]->computeAABB();
    }
    if (manager_) manager_->update();
  }

  /// The objects in a broadphase manager, made at the first call: only
  /// FCL-only checks and distances ask for it (the sphere tier hands FCL
  /// the objects pair by pair), and registering them took 2 % of a
  /// MotionBenchMaker plan's time under perf.
  fcl::DynamicAABBTreeCollisionManagerd& manager() {
    if (!manager_) {
      manager_ = std::make_unique<fcl::DynamicAABBTreeCollisionManagerd>();
      for (const std::unique_ptr<Object>& object : objects) manager_->registerObject(object.get());
      manager_->setup();
    }
    return *manager_;
  }

 private:
  std::unique_ptr<fcl::DynamicAABBTreeCollisionManagerd> manager_;
};

struct CollisionScene::Impl {
  const CollisionModel& model;
  const Scene scene;
  std::vector<std::unique_ptr<Tag>> tags;
  std::vector<std::unique_ptr<Object>> environmentObjects;
  std::vector<std::unique_ptr<Object>> meshBounds;  ///< Tag::bound of the meshes
  fcl::DynamicAABBTreeCollisionManagerd environment;
  std::unique_ptr<SphereTier> tier;
  /// The clearance the scene's requests keep (CollisionScene's; 0: none),
  /// and the tier whose spheres are grown by it (null without one).
  double clearance = 0.0;
  std::unique_ptr<SphereTier> clearanceTier;
  /// Per link: no joint moves it. Per link pair: the clearance rule keeps
  /// them apart (keepsClearance).
  std::vector<bool> still;
  std::vector<std::vector<bool>> keepApart;
  // The grasp rule's target and its surface (shared, or built here on
  // first need, once for all threads).
  const db::ObjectGeometry* target = nullptr;
  const ObjectSurface* sharedSurface = nullptr;
  mutable std::once_flag surfaceBuilt;
  mutable std::unique_ptr<ObjectSurface> ownSurface;

  Impl(const CollisionModel& m, const Scene& s, double c) : model(m), scene(s), clearance(c) {
    if (c <= 0.0) return;  // keepsClearance is only asked with a clearance
    const RobotModel& robot = m.robot;
    const auto links = static_cast<int>(robot.links().size());
    keepApart.assign(static_cast<std::size_t>(links),
                     std::vector<bool>(static_cast<std::size_t>(links), false));
    for (int a = 0; a < links; ++a) {
      still.push_back(robot.movingJointsBetween(a, -1) == 0);
      for (int b = 0; b < links; ++b)
        keepApart[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)] =
            !(robot.isHandLink(a) && robot.isHandLink(b)) &&
            robot.movingJointsBetween(a, b) > kClearanceJointsApart;
    }
  }

  const ObjectSurface* surface() const {
    if (sharedSurface != nullptr || target == nullptr) return sharedSurface;
    std::call_once(surfaceBuilt, [this] { ownSurface = std::make_unique<ObjectSurface>(*target); });
    return ownSurface.get();
  }

  /// `vertices` (one per row, the geometry's frame): a mesh's, whose
  /// bounding box becomes its Tag::bound; empty for a primitive.
  void addEnvironment(const Geometry& geometry, const Eigen::Isometry3d& pose, Tag value,
                      std::mutex* creation = nullptr, const Vertices& vertices = {}) {
    std::unique_ptr<Object> object;
    {
      std::unique_lock<std::mutex> lock;
      if (creation != nullptr) lock = std::unique_lock<std::mutex>(*creation);
      object = std::make_unique<Object>(geometry, pose.linear(), pose.translation());
      object->computeAABB();  // reads the geometry's local box
    }
    value.order = tags.size();
    if (vertices.rows() > 0) {
      const Eigen::Vector3d low = vertices.colwise().minCoeff(),
                            high = vertices.colwise().maxCoeff();
      auto box = std::make_unique<Object>(fcl_query::primitive(0, high - low), pose.linear(),
                                          pose * ((low + high) / 2));
      box->computeAABB();
      value.bound = box.get();
      meshBounds.push_back(std::move(box));
    }
    tags.push_back(std::make_unique<Tag>(std::move(value)));
    object->setUserData(tags.back().get());
    environment.registerObject(object.get());
    environmentObjects.push_back(std::move(object));
  }

  /// The sphere tier over the environment objects (same order), with the
  /// pairs that cannot change (links fixed to the base) dropped where FCL
  /// finds them clear; the clearance tier beside it when the scene keeps one.
  void addSphereTier(std::vector<SphereTier::Item> items);

  /// The clearance rule (collision_checker.h, CollisionScene): whether a
  /// link keeps the clearance from an environment object (the target, or
  /// an obstacle) under a request of the grasp rule or not. Links that
  /// never move need only be free, and so does the hand (the palm and its
  /// fingers, RobotModel::isHandLink) against the target, and against
  /// everything under the grasp rule.
  bool keepsClearance(int link, bool againstTarget, bool graspRule) const {
    if (still[static_cast<std::size_t>(link)]) return false;
    return !(model.robot.isHandLink(link) && (againstTarget || graspRule));
  }
  /// Whether two links keep the clearance from each other: not two hand
  /// links (the hand's own shape: an open hand's fingers lie close), nor
  /// two links at most kClearanceJointsApart moving joints apart (a
  /// wrist's links lie close by the arm's build, whatever the path).
  bool keepsClearance(int a, int b) const {
    return keepApart[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)];
  }
};

}  // namespace hfts::robot
