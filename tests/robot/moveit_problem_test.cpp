// MoveIt planning scenes and motion plan requests (robot/moveit_problem.h)
// on MotionBenchMaker problems (tests/data/mbm) with its Panda model.
#include "robot/moveit_problem.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <fstream>

#include "robot_fixture.h"
#include "test_meshes.h"

namespace hfts::robot {
namespace {

namespace fs = std::filesystem;

const RobotModel& panda() {
  static const RobotModel model =
      RobotModel::load(test::sourcePath("robots/panda_mbm/panda_mbm.json"));
  return model;
}

fs::path problem(const std::string& scenario, const std::string& file) {
  return test::sourcePath("tests/data/mbm/" + scenario + "/" + file);
}

TEST(MoveItProblem, TheMbmPandaIsAnArmWithTheSrdfsDisabledPairs) {
  EXPECT_FALSE(panda().hasHand());
  EXPECT_EQ(panda().numDofs(), 7);
  // 34 <disable_collisions> in the SRDF, every one a pair of the model's links.
  EXPECT_EQ(panda().disabledCollisions().size(), 34u);
  EXPECT_TRUE(panda().isCollisionDisabled(panda().linkIndex("panda_link0"),
                                          panda().linkIndex("panda_link1")));
  EXPECT_FALSE(panda().isCollisionDisabled(panda().linkIndex("panda_link0"),
                                           panda().linkIndex("panda_link6")));
}

TEST(MoveItProblem, ReadsTheSceneStartAndGoal) {
  const MoveItProblem p = loadMoveItProblem(panda(), problem("box_panda", "scene0001.yaml"),
                                            problem("box_panda", "request0001.yaml"));
  EXPECT_EQ(p.scene.name, "scene0001");
  EXPECT_TRUE(p.scene.target_object.empty());
  EXPECT_TRUE(p.scene.robot_base.isApprox(Eigen::Isometry3d::Identity()));
  ASSERT_EQ(p.scene.obstacles.size(), 7u);  // 7 objects of one primitive each
  const Obstacle* can = p.scene.obstacle("Can1");
  ASSERT_NE(can, nullptr);
  EXPECT_EQ(can->type, Obstacle::Type::kCylinder);
  EXPECT_DOUBLE_EQ(can->size.x(), 0.03) << "radius";
  EXPECT_DOUBLE_EQ(can->size.y(), 0.14) << "height: MoveIt gives [height, radius]";
  EXPECT_TRUE(can->pose.translation().isApprox(
      Eigen::Vector3d(0.5408380884576693, 0.3580155146897772, -0.3762264457751537)));
  const Obstacle* base = p.scene.obstacle("base");
  ASSERT_NE(base, nullptr);
  EXPECT_EQ(base->type, Obstacle::Type::kBox);
  EXPECT_TRUE(base->size.isApprox(Eigen::Vector3d(0.7, 0.7, 0.04)));
  Eigen::VectorXd start(7), goal(7);
  start << 0, -0.785, 0, -2.356, 0, 1.571, 0.785;
  goal << 0.4534448383669427, 1.7628, 0.1941262264518609, -0.8667848896139277, -0.3798524112731043,
      2.606927984171601, -0.1898611792470702;
  EXPECT_TRUE(p.start.isApprox(start));
  EXPECT_TRUE(p.goal.isApprox(goal));
  EXPECT_TRUE(p.stricter_pairs.empty())
      << p.stricter_pairs.front().first << " - " << p.stricter_pairs.front().second;
}

TEST(MoveItProblem, EveryCommittedProblemLoads) {
  std::size_t loaded = 0;
  for (const auto& scenario : fs::directory_iterator(test::sourcePath("tests/data/mbm"))) {
    if (!scenario.is_directory()) continue;
    for (const char* n : {"0001", "0002"}) {
      const MoveItProblem p =
          loadMoveItProblem(panda(), scenario.path() / (std::string("scene") + n + ".yaml"),
                            scenario.path() / (std::string("request") + n + ".yaml"));
      EXPECT_FALSE(p.scene.obstacles.empty()) << scenario.path();
      EXPECT_TRUE(panda().withinLimits(p.start) && panda().withinLimits(p.goal));
      ++loaded;
    }
  }
  EXPECT_EQ(loaded, 14u);
}

/// A copy of box_panda/0001's files with `from` replaced by `to` in one.
struct Edited {
  Edited(bool scene, const std::string& from, const std::string& to) {
    for (const char* file : {"scene0001.yaml", "request0001.yaml"}) {
      std::string text = test::readBytes(problem("box_panda", file));
      if ((std::string(file) == "scene0001.yaml") == scene) {
        const auto at = text.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        if (at != std::string::npos) text.replace(at, from.size(), to);
      }
      std::ofstream(dir / file) << text;
    }
  }
  ~Edited() { fs::remove_all(dir); }
  MoveItProblem load() const {
    return loadMoveItProblem(panda(), dir / "scene0001.yaml", dir / "request0001.yaml");
  }
  fs::path dir = [] {
    fs::path d = fs::temp_directory_path() / ("moveit-problem-" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
};

TEST(MoveItProblem, AnInlineMeshIsAMeshObstacle) {
  // A closed tetrahedron added to Can1 (frame: its primitive pose's parent,
  // the world), at a mesh pose 1 m up.
  const Edited edited(true, "- id: Can1",
                      "- meshes: [{vertices: [{x: 0, y: 0, z: 0}, {x: 0.1, y: 0, z: 0}, {x: 0, "
                      "y: 0.1, z: 0}, {x: 0, y: 0, z: 0.1}], triangles: [{vertex_indices: [0, 2, "
                      "1]}, {vertex_indices: [0, 1, 3]}, {vertex_indices: [0, 3, 2]}, "
                      "{vertex_indices: [1, 2, 3]}]}]\n      mesh_poses: [{position: [0, 0, 1], "
                      "orientation: [0, 0, 0, 1]}]\n      id: Can1");
  const MoveItProblem p = edited.load();
  ASSERT_EQ(p.scene.obstacles.size(), 8u);
  const Obstacle* mesh = p.scene.obstacle("Can1/mesh0");
  ASSERT_NE(mesh, nullptr);
  EXPECT_EQ(mesh->type, Obstacle::Type::kMesh);
  EXPECT_EQ(mesh->mesh.vertices.rows(), 4);
  EXPECT_EQ(mesh->mesh.triangles.rows(), 4);
  EXPECT_TRUE(mesh->pose.translation().isApprox(Eigen::Vector3d(0, 0, 1)));
  ASSERT_TRUE(mesh->distance_grid);
  EXPECT_NE(p.scene.obstacle("Can1"), nullptr) << "the object's primitive stays";
}

void expectRejected(bool scene, const std::string& from, const std::string& to,
                    const std::vector<std::string>& words) {
  const Edited edited(scene, from, to);
  test::expectErrorMentioning<SceneError>([&] { edited.load(); }, words);
}

TEST(MoveItProblem, WhatItCannotUseIsNamed) {
  expectRejected(true, "type: cylinder", "type: cone",
                 {"scene0001.yaml", "world.collision_objects[0].primitives[0].type",
                  "'cone' is not supported"});
  expectRejected(true, "dimensions: [0.14, 0.03]", "dimensions: [0.14]",
                 {"world.collision_objects[0].primitives[0].dimensions", "list of 2 numbers"});
  expectRejected(true, "dimensions: [0.14, 0.03]", "dimensions: [0.14, -0.03]",
                 {"dimensions: must be positive"});
  expectRejected(true, "- id: Can1", "- planes: [{coef: [0, 0, 1, 0]}]\n      id: Can1",
                 {"world.collision_objects[0].planes", "not supported"});
  expectRejected(true, "- id: Can1",
                 "- meshes: [{vertices: [{x: 0, y: 0, z: 0}, {x: 1, y: 0, z: 0}, {x: 0, y: 1, "
                 "z: 0}], triangles: [{vertex_indices: [0, 1, 3]}]}]\n      mesh_poses: "
                 "[{position: [0, 0, 0], orientation: [0, 0, 0, 1]}]\n      id: Can1",
                 {"world.collision_objects[0].meshes[0].triangles[0].vertex_indices",
                  "indices of the 3 vertices"});
  expectRejected(false, "position: 1.7628", "position: 9", {"request0001.yaml", "panda_joint2"});
  expectRejected(false, "joint_name: panda_joint1", "joint_name: panda_joint9",
                 {"goal_constraints[0].joint_constraints", "no value for joint 'panda_joint1'"});
  expectRejected(false, "goal_constraints:", "goal_constraint:", {"goal_constraints: is required"});
  expectRejected(true, "robot_state:", "robot_state: [\n", {"scene0001.yaml", "not valid YAML"});
  test::expectErrorMentioning<SceneError>(
      [] { loadMoveItProblem(panda(), "/nonexistent/scene.yaml", "/nonexistent/request.yaml"); },
      {"/nonexistent/scene.yaml", "cannot read"});
}

}  // namespace
}  // namespace hfts::robot
