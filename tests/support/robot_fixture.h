#pragma once
// The bundled robot and scenes for planner tests.

#include <filesystem>

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

}  // namespace hfts::test
