// A hand map file (HDF5) through loadHandMap, then the reachability index
// the planning world builds from it for the bundled robot. A bad file must
// throw DatabaseError, a map of another hand ModelError.

#include <cstddef>
#include <cstdint>

#include "fuzz_files.h"
#include "grasp/hand_reachability.h"
#include "hfts_db/hand_map.h"
#include "robot/robot_model.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hfts;
  static fuzz::ScratchFile file("hand_map", ".h5");
  static const robot::RobotModel robot =
      robot::RobotModel::load(std::string(HFTS_SOURCE_DIR) + "/robots/kr5_sdh/kr5_sdh.json");
  db::HandMap map;
  try {
    map = db::loadHandMap(file.write(data, size));
  } catch (const db::DatabaseError&) {
    return 0;
  }
  try {
    const grasp::HandReachability reachability(robot, std::move(map));
  } catch (const robot::ModelError&) {
  }
  return 0;
}
