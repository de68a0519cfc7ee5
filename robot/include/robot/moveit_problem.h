#pragma once
// A motion planning problem in MoveIt's YAML form (docs/motionbenchmaker.md):
// a planning scene (moveit_msgs/PlanningScene: its world's collision
// objects, the robot's virtual joint, the allowed-collision matrix) and a
// motion plan request (moveit_msgs/MotionPlanRequest: the start state and
// joint constraints as the goal), as MotionBenchMaker publishes them.

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "robot/robot_model.h"
#include "robot/scene.h"

namespace hfts::robot {

struct MoveItProblem {
  /// The collision objects as obstacles (boxes, cylinders, spheres, and
  /// inline meshes with their distance grids; an object of several
  /// primitives gives one obstacle each, named "<id>/<k>", its meshes
  /// "<id>/mesh<k>"), the robot's base where the virtual joint puts it; no
  /// target object. Named after the scene file's stem.
  Scene scene;
  Eigen::VectorXd start;  ///< the robot's DoF order
  Eigen::VectorXd goal;   ///< the joint constraints' positions, the robot's DoF order
  /// Robot link pairs the problem's allowed-collision matrix allows but the
  /// robot model checks (its disabled pairs differ): the model is then
  /// stricter than the problem.
  std::vector<std::pair<std::string, std::string>> stricter_pairs;
};

/// Reads a planning scene and a motion plan request for `robot`: every
/// DoF's start from the request's start state (else the scene's robot
/// state), the goal from the request's first goal constraint's joint
/// constraints (each DoF once; joints that are not DoFs of the robot are
/// left out). Throws SceneError naming the file and the key for what it
/// cannot use: a file that is not YAML, a missing key, a primitive other
/// than a box, cylinder or sphere, planes, a mesh whose indices are not its
/// vertices', a DoF without a start or a goal, a value outside the joint
/// limits.
MoveItProblem loadMoveItProblem(const RobotModel& robot, const std::filesystem::path& sceneYaml,
                                const std::filesystem::path& requestYaml);

}  // namespace hfts::robot
