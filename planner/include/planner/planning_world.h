#pragma once
// What plans are made with: the robot, its collision model and IK, the hand
// reachability map and the object databases (with their collision meshes),
// loaded once and shared by every plan and thread.

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "grasp/hand_reachability.h"
#include "hfts_db/hand_map.h"
#include "hfts_db/object_database.h"
#include "robot/arm_ik.h"
#include "robot/collision_model.h"
#include "robot/motion_bound.h"
#include "robot/robot_model.h"

namespace hfts::robot {
class CollisionMesh;
class ObjectSurface;
}  // namespace hfts::robot

namespace hfts::planner {

/// The object databases of a folder with their collision hierarchies and
/// exact surfaces.
/// Immutable once built; the worlds of several robots share one.
class ObjectLibrary {
 public:
  explicit ObjectLibrary(std::map<std::string, db::ObjectDatabase> objects);
  ~ObjectLibrary();
  ObjectLibrary(const ObjectLibrary&) = delete;
  ObjectLibrary& operator=(const ObjectLibrary&) = delete;

  /// Loads every `*.h5` of `dbDir` but hand maps (`*_hand_map.h5`, of any
  /// robot) as an object database. A database that fails to load is
  /// skipped and its error appended to `skipped` (when given); a missing
  /// directory throws std::runtime_error naming it.
  static std::shared_ptr<const ObjectLibrary> load(const std::filesystem::path& dbDir,
                                                   std::vector<std::string>* skipped = nullptr);

  /// nullptr for an unknown name.
  const db::ObjectDatabase* object(const std::string& name) const;
  /// The collision hierarchy of an object's mesh; nullptr for an unknown name.
  const robot::CollisionMesh* collisionMesh(const std::string& name) const;
  /// The object's exact surface (signed distances, the mesh's normals);
  /// nullptr for an unknown name.
  const robot::ObjectSurface* surface(const std::string& name) const;
  std::vector<std::string> names() const;

 private:
  std::map<std::string, db::ObjectDatabase> objects_;
  std::map<std::string, std::unique_ptr<const robot::CollisionMesh>> collision_meshes_;
  std::map<std::string, std::unique_ptr<const robot::ObjectSurface>> surfaces_;
};

/// What plans are made with: the robot, its hand reachability map and the
/// object databases. Immutable once built; share it between threads.
class PlanningWorld {
 public:
  /// Throws ModelError when the map does not belong to the robot.
  PlanningWorld(robot::RobotModel robot, db::HandMap handMap,
                std::map<std::string, db::ObjectDatabase> objects);
  /// A world whose objects another robot's world shares.
  PlanningWorld(robot::RobotModel robot, db::HandMap handMap,
                std::shared_ptr<const ObjectLibrary> objects);
  /// The world of an arm without a hand (motion-only, RobotModel::hasHand
  /// false): no hand map. Throws ModelError for a robot with a hand.
  PlanningWorld(robot::RobotModel robot, std::shared_ptr<const ObjectLibrary> objects);
  /// A motion-only world over a collision model already built (the robot
  /// holding an object, robot::withHeldBody): no hand map, so it plans
  /// motions to goals, never grasps (canGrasp() is false).
  PlanningWorld(std::shared_ptr<const robot::CollisionModel> model,
                std::shared_ptr<const ObjectLibrary> objects);
  ~PlanningWorld();
  PlanningWorld(const PlanningWorld&) = delete;
  PlanningWorld& operator=(const PlanningWorld&) = delete;

  /// Loads the robot config, `<robot name>_hand_map.h5` from `dbDir` (not
  /// for an arm without a hand) and
  /// the object databases there (ObjectLibrary::load, which appends what
  /// it skipped to `skipped`); a missing directory, robot or hand map
  /// throws (std::runtime_error naming the file).
  static std::shared_ptr<const PlanningWorld> load(const std::filesystem::path& robotConfig,
                                                   const std::filesystem::path& dbDir,
                                                   std::vector<std::string>* skipped = nullptr);
  /// The same with objects already loaded (a server with several robots).
  static std::shared_ptr<const PlanningWorld> load(const std::filesystem::path& robotConfig,
                                                   const std::filesystem::path& dbDir,
                                                   std::shared_ptr<const ObjectLibrary> objects);

  const robot::RobotModel& robot() const { return robot_; }
  /// Whether it plans grasps: a robot with a hand and its hand map.
  bool canGrasp() const { return fast_.has_value(); }
  /// The robot's collision model (spheres, pair maps), built with the world.
  const robot::CollisionModel& collisionModel() const { return *collision_; }
  /// How far the robot's links can move per joint step: what certified
  /// motions are proven with (robot::certifyPath).
  const robot::MotionBound& motionBound() const { return bound_; }
  const robot::ArmIk& ik() const { return ik_; }
  /// The map's fast query (the HFTS objective) and thorough query (Phi(h)).
  /// Throw std::logic_error for an arm without a hand (grasps are refused
  /// before they are asked).
  const grasp::HandReachability& handMap() const;
  const grasp::HandReachability& thoroughHandMap() const;
  /// nullptr for an unknown name.
  const db::ObjectDatabase* object(const std::string& name) const { return objects_->object(name); }
  /// The collision hierarchy of an object's mesh, built once with the
  /// objects; nullptr for an unknown name.
  const robot::CollisionMesh* collisionMesh(const std::string& name) const {
    return objects_->collisionMesh(name);
  }
  /// The object's exact surface, built once with the objects; nullptr for
  /// an unknown name.
  const robot::ObjectSurface* surface(const std::string& name) const {
    return objects_->surface(name);
  }
  std::vector<std::string> objectNames() const { return objects_->names(); }
  const std::shared_ptr<const ObjectLibrary>& objects() const { return objects_; }
  /// The smallest fingertip's pad radius (robot::smallestPadRadius): the
  /// room a finger needs beside a contact.
  double padRadius() const { return padRadius_; }

 private:
  robot::RobotModel robot_;
  std::shared_ptr<const robot::CollisionModel> collision_;
  robot::MotionBound bound_;
  robot::ArmIk ik_;
  std::optional<grasp::HandReachability> fast_;
  std::optional<grasp::HandReachability> thorough_;
  std::shared_ptr<const ObjectLibrary> objects_;
  double padRadius_ = 0.0;
};

}  // namespace hfts::planner
