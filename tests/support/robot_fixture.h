#pragma once
// The bundled robot and scenes for planner tests.

#include <filesystem>
#include <map>
#include <memory>
#include <mutex>

#include "robot/collision_model.h"
#include "robot/robot_model.h"

namespace hfts::test {

inline std::filesystem::path sourcePath(const std::string& relative) {
  return std::filesystem::path(HFTS_SOURCE_DIR) / relative;
}

/// The KR5 sixx R850 + SDH model, loaded once.
inline const robot::RobotModel& kr5Sdh() {
  static const robot::RobotModel model =
      robot::RobotModel::load(sourcePath("robots/kr5_sdh/kr5_sdh.json"));
  return model;
}

/// The collision model of a test's robot, built once per model. Only for
/// models that live until the program ends (the fixtures' statics): the
/// model's address is the key.
inline const robot::CollisionModel& collisionOf(const robot::RobotModel& model) {
  static std::mutex mutex;
  static std::map<const robot::RobotModel*, std::shared_ptr<const robot::CollisionModel>> built;
  const std::lock_guard<std::mutex> lock(mutex);
  std::shared_ptr<const robot::CollisionModel>& entry = built[&model];
  if (!entry) entry = robot::buildCollisionModel(model);
  return *entry;
}

}  // namespace hfts::test
