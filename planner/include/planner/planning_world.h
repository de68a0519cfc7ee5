#pragma once
// What plans are made with: the robot, its IK, the hand reachability map
// and the object databases (with their collision meshes), loaded once and
// shared by every plan and thread.

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "grasp/hand_reachability.h"
#include "hfts_db/hand_map.h"
#include "hfts_db/object_database.h"
#include "robot/arm_ik.h"
#include "robot/robot_model.h"

namespace hfts::robot {
class CollisionMesh;
}  // namespace hfts::robot

namespace hfts::planner {

/// What plans are made with: the robot, its hand reachability map and the
/// object databases. Immutable once built; share it between threads.
class PlanningWorld {
 public:
  /// Throws ModelError when the map does not belong to the robot.
  PlanningWorld(robot::RobotModel robot, db::HandMap handMap,
                std::map<std::string, db::ObjectDatabase> objects);
  ~PlanningWorld();
  PlanningWorld(const PlanningWorld&) = delete;
  PlanningWorld& operator=(const PlanningWorld&) = delete;

  /// Loads the robot config, `<robot name>_hand_map.h5` from `dbDir` and
  /// every other `*.h5` there but hand maps (`*_hand_map.h5`, of any
  /// robot) as an object database. An object database
  /// that fails to load is skipped and its error appended to `skipped`
  /// (when given); a missing directory, robot or hand map throws
  /// (std::runtime_error naming the file).
  static std::shared_ptr<const PlanningWorld> load(const std::filesystem::path& robotConfig,
                                                   const std::filesystem::path& dbDir,
                                                   std::vector<std::string>* skipped = nullptr);

  const robot::RobotModel& robot() const { return robot_; }
  const robot::ArmIk& ik() const { return ik_; }
  /// The map's fast query (the HFTS objective) and thorough query (Phi(h)).
  const grasp::HandReachability& handMap() const { return fast_; }
  const grasp::HandReachability& thoroughHandMap() const { return thorough_; }
  /// nullptr for an unknown name.
  const db::ObjectDatabase* object(const std::string& name) const;
  /// The collision hierarchy of an object's mesh, built once with the
  /// world; nullptr for an unknown name.
  const robot::CollisionMesh* collisionMesh(const std::string& name) const;
  std::vector<std::string> objectNames() const;
  /// The smallest fingertip's pad radius (robot::smallestPadRadius): the
  /// room a finger needs beside a contact.
  double padRadius() const { return padRadius_; }

 private:
  robot::RobotModel robot_;
  robot::ArmIk ik_;
  grasp::HandReachability fast_;
  grasp::HandReachability thorough_;
  std::map<std::string, db::ObjectDatabase> objects_;
  std::map<std::string, std::unique_ptr<const robot::CollisionMesh>> collisionMeshes_;
  double padRadius_ = 0.0;
};

}  // namespace hfts::planner
