#include "planner/sampling_tools.h"

#include <gtest/gtest.h>

#include <map>
#include <string>

#include "grasp/hand_map_builder.h"
#include "preprocess/database_builder.h"
#include "robot_fixture.h"
#include "test_meshes.h"

namespace hfts::planner {
namespace {

/// The Panda with its hand map and the box, the only object these tests need.
const PlanningWorld& pandaWorld() {
  static const PlanningWorld world = [] {
    const robot::RobotModel panda =
        robot::RobotModel::load(test::sourcePath("robots/panda_gripper/panda_gripper.json"));
    std::map<std::string, db::ObjectDatabase> objects;
    objects.emplace(
        "box",
        preprocess::buildObjectDatabaseFromFile(test::bundledMeshDir() / "box.stl", {}).database);
    return PlanningWorld(panda, grasp::buildHandMap(panda, grasp::handMapOptions(panda)),
                         std::move(objects));
  }();
  return world;
}

/// A ball obstacle named "ball".
robot::Obstacle ball(const Eigen::Vector3d& at, double radius) {
  robot::Obstacle o;
  o.name = "ball";
  o.type = robot::Obstacle::Type::kSphere;
  o.size << radius, 0, 0;
  o.pose.translation() = at;
  return o;
}

/// A leaf of the box whose grasp the jaws hold (Q > 0) with a free turn.
grasp::HftsNode heldLeaf(const grasp::HftsSpace& space) {
  grasp::GraspObjective plain(space, pandaWorld().handMap(),
                              grasp::objectiveOptions(pandaWorld().robot()));
  for (std::uint64_t i = 0;; ++i) {
    grasp::HftsNode node = space.child(space.root(), (i * 7919) % space.numChildren(space.root()));
    while (!space.isLeaf(node)) node = space.child(node, (i * 31) % space.numChildren(node));
    if (plain.evaluate(node).quality > 0.0) return node;
  }
}

/// Whether the objective of tools built with `turns` finds the leaf's hand
/// blocked by a ball of `radius` at `centre` (R(h)'s own palm position when
/// not given).
bool blocked(int turns, double radius, const Eigen::Vector3d* centre = nullptr) {
  const PlanningWorld& world = pandaWorld();
  const db::ObjectDatabase& box = *world.object("box");
  robot::Scene scene;
  scene.target_object = "box";
  scene.target_pose.translation() = Eigen::Vector3d(0.5, 0.0, 0.25);
  const grasp::HftsSpace space(box, 2);
  const grasp::HftsNode leaf = heldLeaf(space);
  const grasp::GraspContacts contacts = space.representative(leaf);
  const grasp::HandQuery hand = world.handMap().query(contacts.positions, contacts.outward_normals);
  EXPECT_TRUE(hand.free_turn.has_value());
  scene.obstacles.push_back(
      ball(centre != nullptr ? *centre : scene.target_pose * hand.palm_pose.translation(), radius));
  robot::CollisionChecker checker(world.collisionModel(), scene, &box.geometry,
                                  world.collisionMesh("box"));
  GoalSamplingSettings settings;
  settings.hand_clearance = 1;
  settings.palm_turns = turns;
  SamplingTools tools(world, scene, space, checker, settings);
  EXPECT_EQ(tools.configurator.turns(), turns);
  return tools.objective.evaluate(leaf).hand_blocked;
}

TEST(SamplingTools, AGrippersHandIsBlockedOnlyWhenItIsAtEveryPalmTurn) {
  // A ball where R(h)'s own pose puts the palm: that turn alone is blocked.
  EXPECT_TRUE(blocked(1, 0.03));
  EXPECT_FALSE(blocked(8, 0.03));
  // A ball around the whole box: every turn.
  const Eigen::Vector3d centre(0.5, 0.0, 0.31);
  EXPECT_TRUE(blocked(8, 0.3, &centre));
}

}  // namespace
}  // namespace hfts::planner
