#pragma once
// The physics tests' world: the bundled 4.6 cm cube on a table in front of
// the Panda, the palm above it pointing down (the robot's own IK), the jaws
// open around it (pre-grasp) and closed until the pads touch its faces
// (grasp).

#include <gtest/gtest.h>

#include <random>

#include "bundled_objects.h"
#include "robot/arm_ik.h"
#include "robot/robot_model.h"
#include "robot/scene.h"
#include "robot_fixture.h"

namespace hfts::test {

/// The Panda + Franka Hand, loaded once.
inline const robot::RobotModel& panda() {
  static const robot::RobotModel model =
      robot::RobotModel::load(sourcePath("robots/panda_gripper/panda_gripper.json"));
  return model;
}

/// The bundled small cube (4.6 cm edges; its origin in the middle of its
/// bottom face), built once.
inline const db::ObjectDatabase& smallCube() {
  static const db::ObjectDatabase cube = bundledObject(bundledMeshDir() / "small_cube.stl");
  return cube;
}

/// The Panda's fingertip pads are 103.4 mm below the palm origin along its z.
constexpr double kPandaPadDepth = 0.1034;

struct PandaCube {
  PandaCube() {
    robot::Obstacle table;
    table.name = "table";
    table.type = robot::Obstacle::Type::kBox;
    table.size = Eigen::Vector3d(0.6, 0.8, 0.04);
    table.pose.translation() = Eigen::Vector3d(0.55, 0.0, -0.021);  // top at z = -1 mm
    scene.name = "panda_cube";
    scene.obstacles.push_back(table);
    scene.target_object = "small_cube";
    scene.target_pose.translation() = Eigen::Vector3d(0.5, 0.0, 0.0);
    scene.target_rest_on = "table";
    scene.target_pose = robot::targetPose(scene, smallCube().geometry.mesh_vertices);
    // Palm straight down (z to -z of the world), the jaws along the world y
    // axis, the pads at the cube's centre.
    Eigen::Isometry3d palm = Eigen::Isometry3d::Identity();
    palm.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
    palm.translation() = center() + Eigen::Vector3d(0, 0, kPandaPadDepth);
    const robot::ArmIk ik(panda());
    std::mt19937_64 rng(1);
    const auto solutions = ik.solvePalm(palm, rng);
    EXPECT_FALSE(solutions.empty()) << "the Panda cannot put its palm above the cube";
    grasp = Eigen::VectorXd::Zero(panda().numDofs());
    if (!solutions.empty()) grasp.head(7) = solutions.front();
    grasp(7) = halfWidth();  // each jaw at the cube's face
    pregrasp = grasp;
    pregrasp(7) = halfWidth() + panda().pregraspOffset();
  }

  static double halfWidth() { return smallCube().geometry.bbox_max.y(); }
  /// The cube's centre in the world.
  Eigen::Vector3d center() const {
    const db::ObjectGeometry& g = smallCube().geometry;
    return scene.target_pose * ((g.bbox_min + g.bbox_max) / 2.0);
  }

  robot::Scene scene;
  Eigen::VectorXd pregrasp, grasp;
};

}  // namespace hfts::test
