#pragma once
// `hfts-preprocess --check-robot ROBOT.json`: whether a robot config and its
// URDF are fit for planning, each finding with what to fix (docs/robots.md).

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace hfts::preprocess {

/// One finding of the check.
struct RobotFinding {
  enum class Level { kOk, kWarning, kError };
  Level level = Level::kOk;
  std::string topic;    ///< what was checked: "model", "hand", "arm IK", "home", ...
  std::string message;  ///< what was found and, for problems, what to change
};

/// Loads the robot and checks, in order: the config and URDF themselves
/// (every ModelError, naming the key), the hand (2 to 4 fingertips below
/// the palm, how many random hand postures are grasp postures), the arm
/// (IK of random poses round-trips), home and the open hand free of self
/// collisions, link pairs that collide in most random postures (missing
/// from disabled_collisions), the sphere model, and the optional limits.
/// Never throws for a bad robot: problems are findings.
std::vector<RobotFinding> checkRobot(const std::filesystem::path& config);

/// Prints the findings, one per line; returns the exit code (0 without
/// errors, 1 with).
int printRobotFindings(const std::vector<RobotFinding>& findings, std::ostream& out);

}  // namespace hfts::preprocess
