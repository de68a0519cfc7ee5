#include "graspability_report.h"

#include <exception>

#include "grasp/hand_reachability.h"
#include "hfts_db/hand_map.h"
#include "robot/robot_model.h"

namespace hfts::preprocess {

GraspabilityReport graspabilityReport(const db::ObjectDatabase& object,
                                      const std::filesystem::path& databaseFile,
                                      const std::filesystem::path& robotConfig) {
  constexpr double kTolerance = 0.005;  // m: the planner's max_fingertip_error default
  GraspabilityReport report;
  report.tolerance = kTolerance;
  try {
    const robot::RobotModel robot = robot::RobotModel::load(robotConfig);
    report.robot = robot.name();
    const std::filesystem::path mapPath =
        databaseFile.parent_path() / (robot.name() + "_hand_map.h5");
    if (!std::filesystem::exists(mapPath)) {
      report.note = "no hand map " + mapPath.string() + " (build it with hfts-preprocess --hand " +
                    robotConfig.string() + " -o " + databaseFile.parent_path().string() + ")";
      return report;
    }
    const db::HandMap map = db::loadHandMap(mapPath);
    const grasp::HandReachability fast(robot, map);
    const grasp::HandReachability thorough(robot, map, grasp::HandQueryOptions::thorough());
    const grasp::HftsSpace space(object, static_cast<int>(robot.fingertips().size()));
    report.value = grasp::graspability(space, fast, thorough, grasp::objectiveOptions(robot), 1000,
                                       kTolerance);
  } catch (const std::exception& e) {
    report.note = e.what();
  }
  return report;
}

}  // namespace hfts::preprocess
