#pragma once
// The graspability line of `hfts-preprocess --inspect`: how graspable the
// object is for a robot's hand in free space (grasp/graspability.h).

#include <filesystem>
#include <optional>
#include <string>

#include "grasp/graspability.h"
#include "hfts_db/object_database.h"

namespace hfts::preprocess {

struct GraspabilityReport {
  std::string robot;  ///< the robot's name, when its config loaded
  std::optional<grasp::Graspability> value;
  double tolerance = 0.0;  ///< R(h) bound of "reachable" (m)
  std::string note;        ///< why there is no value (no hand map, ...)
};

/// The object's graspability for the robot of `robotConfig`, with that
/// robot's hand map `<robot>_hand_map.h5` beside `databaseFile`. Never
/// throws for a missing or unreadable robot or map: the note says what is
/// missing and how to build it.
GraspabilityReport graspabilityReport(const db::ObjectDatabase& object,
                                      const std::filesystem::path& databaseFile,
                                      const std::filesystem::path& robotConfig);

}  // namespace hfts::preprocess
