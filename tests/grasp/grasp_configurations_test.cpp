#include "grasp/grasp_configurations.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "bundled_objects.h"
#include "grasp/grasp_optimizer.h"
#include "robot/kinematics.h"
#include "robot_fixture.h"
#include "test_meshes.h"

namespace hfts::grasp {
namespace {

const robot::RobotModel& m() {
  return test::kr5Sdh();
}

const db::HandMap& handMap() {
  static const db::HandMap map = buildHandMap(m());
  return map;
}

/// An empty scene with the object floating in front of the robot.
robot::Scene freeSpace(const std::string& object, const Eigen::Vector3d& at) {
  robot::Scene scene;
  scene.target_object = object;
  scene.target_pose.translation() = at;
  return scene;
}

TEST(GraspConfigurations, GraspsInFreeSpaceGiveFreeGoalsWithFingertipsOnTheContacts) {
  const HandReachability fast(m(), handMap());
  const HandReachability thorough(m(), handMap(), HandQueryOptions::thorough());
  const robot::ArmIk ik(m());
  for (const auto& [name, database] : test::bundledObjects()) {
    SCOPED_TRACE(name);
    const robot::Scene scene = freeSpace(name, {0.6, 0.0, 0.15});
    robot::CollisionChecker checker(test::collisionOf(m()), scene, &database.geometry);
    GraspConfigurator configurator(m(), ik, thorough, checker, scene.target_pose, scene.robot_base);
    const HftsSpace space(database, 3);
    GraspObjective objective(space, fast);
    std::mt19937_64 rng(8);
    bool found = false;
    // Up to 150 root-to-leaf climbs: the thin profiles of the zoo have few
    // stable, reachable leaves (graspability 0.2-2 %).
    for (int restart = 0; restart < 150 && !found; ++restart) {
      const ClimbResult leaf = optimizeToLeaf(objective, 30, rng);
      if (leaf.evaluation.quality <= 0) continue;
      const auto all = configurator.configure(space, leaf.best, rng);
      for (const GraspConfiguration& c : all.configurations) {
        if (c.label != ConfigurationLabel::kCollisionFree) continue;
        EXPECT_TRUE(m().withinLimits(c.pregrasp));
        EXPECT_FALSE(checker.inCollision(c.pregrasp));
        found = c.fingertip_error < 0.005;
        if (found) break;
      }
    }
    EXPECT_TRUE(found) << "no collision-free goal with fingertips within 5 mm";
  }
}

TEST(GraspConfigurations, UnreachableAndBlockedGraspsAreLabelled) {
  const HandReachability thorough(m(), handMap(), HandQueryOptions::thorough());
  const robot::ArmIk ik(m());
  const db::ObjectDatabase& box = test::bundledObjects().at("box");
  const HftsSpace space(box, 3);
  std::mt19937_64 rng(9);
  const HftsNode node = space.child(space.root(), 777);

  robot::Scene far = freeSpace("box", {2.5, 0.0, 0.1});
  robot::CollisionChecker farChecker(test::collisionOf(m()), far, &box.geometry);
  GraspConfigurator unreachable(m(), ik, thorough, farChecker, far.target_pose, far.robot_base);
  const auto none = unreachable.configure(space, node, rng).configurations;
  ASSERT_EQ(none.size(), 1u);
  EXPECT_EQ(none[0].label, ConfigurationLabel::kNoKinematicSolution);
  EXPECT_EQ(none[0].pregrasp.size(), 0);

  // Find a grasp with IK solutions in free space, then put a ball where its
  // palm goes: every configuration of that grasp must now collide with it.
  robot::Scene open = freeSpace("box", {0.6, 0.0, 0.15});
  robot::CollisionChecker openChecker(test::collisionOf(m()), open, &box.geometry);
  GraspConfigurator freeConfigurator(m(), ik, thorough, openChecker, open.target_pose,
                                     open.robot_base);
  HftsNode reachable = node;
  GraspConfigurations found;
  for (std::uint64_t i = 0; i < 200; ++i) {
    reachable = space.child(space.root(), i * 37);
    found = freeConfigurator.configure(space, reachable, rng);
    if (found.configurations[0].label != ConfigurationLabel::kNoKinematicSolution) break;
  }
  ASSERT_NE(found.configurations[0].label, ConfigurationLabel::kNoKinematicSolution);
  robot::Scene blocked = open;
  robot::Obstacle ball;
  ball.name = "ball";
  ball.type = robot::Obstacle::Type::kSphere;
  ball.size << 0.03, 0, 0;
  ball.pose.translation() = open.target_pose * found.hand.palm_pose.translation();
  blocked.obstacles.push_back(ball);
  robot::CollisionChecker blockedChecker(test::collisionOf(m()), blocked, &box.geometry);
  GraspConfigurator configurator(m(), ik, thorough, blockedChecker, blocked.target_pose,
                                 blocked.robot_base);
  int colliding = 0;
  for (const GraspConfiguration& c : configurator.configure(space, reachable, rng).configurations) {
    EXPECT_EQ(c.label, ConfigurationLabel::kColliding);
    colliding += c.label == ConfigurationLabel::kColliding;
    EXPECT_FALSE(c.collision.first.empty());
  }
  EXPECT_GT(colliding, 0);
}

TEST(GraspConfigurations, PregraspOpensSingleFingerJointsOnly) {
  const HandReachability fast(m(), handMap());
  const robot::ArmIk ik(m());
  robot::Scene scene;
  robot::CollisionChecker checker(test::collisionOf(m()), scene, nullptr);
  const GraspConfigurator configurator(m(), ik, fast, checker, scene.target_pose, scene.robot_base);
  Eigen::VectorXd hand(7);
  hand << 0.7, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5;
  const Eigen::VectorXd open = configurator.openedHand(hand);
  EXPECT_DOUBLE_EQ(open(0), 0.7);  // the knuckle drives two fingers: unchanged
  // Positive flex closes an SDH finger: opening lowers every flex joint.
  for (int h = 1; h < 7; ++h) EXPECT_NEAR(open(h), hand(h) - m().pregraspOffset(), 1e-12);
}

// A DoF that drives several fingers opens them when it moves each along
// its pad normal the same way: a parallel-jaw gripper's mimic jaws.
TEST(GraspConfigurations, PregraspOpensAGrippersMimicJaws) {
  const robot::RobotModel panda =
      robot::RobotModel::load(test::sourcePath("robots/panda_gripper/panda_gripper.json"));
  const HandReachability fast(panda, buildHandMap(panda, handMapOptions(panda)));
  const robot::ArmIk ik(panda);
  robot::Scene scene;
  const auto collision = robot::buildCollisionModel(panda);
  robot::CollisionChecker checker(*collision, scene, nullptr);
  const GraspConfigurator configurator(panda, ik, fast, checker, scene.target_pose,
                                       scene.robot_base);
  const Eigen::VectorXd closed = Eigen::VectorXd::Constant(1, 0.02);
  // Positive jaw travel opens: the jaws move apart by the pre-grasp offset.
  EXPECT_NEAR(configurator.openedHand(closed)(0), 0.02 + panda.pregraspOffset(), 1e-12);
  // At the stop they stay there.
  EXPECT_EQ(configurator.openedHand(Eigen::VectorXd::Constant(1, 0.04))(0), 0.04);
}

const robot::RobotModel& panda() {
  static const robot::RobotModel model =
      robot::RobotModel::load(test::sourcePath("robots/panda_gripper/panda_gripper.json"));
  return model;
}

const robot::RobotModel& ur5eAllegro() {
  static const robot::RobotModel model =
      robot::RobotModel::load(test::sourcePath("robots/ur5e_allegro/ur5e_allegro.json"));
  return model;
}

const HandReachability& pandaHand() {
  static const HandReachability thorough(panda(), buildHandMap(panda(), handMapOptions(panda())),
                                         HandQueryOptions::thorough());
  return thorough;
}

/// Two antipodal contacts 6 cm apart (a box's narrow sides), object frame.
GraspContacts pinch() {
  GraspContacts g{Eigen::Matrix3Xd(3, 2), Eigen::Matrix3Xd(3, 2)};
  g.positions << 0, 0, -0.03, 0.03, 0.06, 0.06;
  g.outward_normals << 0, 0, -1, 1, 0, 0;
  return g;
}

/// A sphere obstacle named `name`.
robot::Obstacle ball(const std::string& name, const Eigen::Vector3d& at, double radius) {
  robot::Obstacle o;
  o.name = name;
  o.type = robot::Obstacle::Type::kSphere;
  o.size << radius, 0, 0;
  o.pose.translation() = at;
  return o;
}

/// Largest distance from a configuration's fingertips to the pinch.
double fingertipDistance(const GraspConfigurations& all, const GraspConfiguration& c,
                         const Eigen::Isometry3d& object) {
  const robot::FingertipFrames tips =
      robot::fingertipFrames(panda(), robot::forwardKinematics(panda(), c.grasp));
  double d = 0;
  for (int i = 0; i < 2; ++i)
    d = std::max(d, (tips.positions.col(all.hand.finger_of_contact[static_cast<std::size_t>(i)]) -
                     object * Eigen::Vector3d(pinch().positions.col(i)))
                        .norm());
  return d;
}

TEST(GraspConfigurations, AGrippersPalmTurnsAboutTheContactLineUntilTheHandFits) {
  const robot::ArmIk ik(panda());
  robot::Scene scene = freeSpace("box", {0.5, 0.0, 0.25});
  std::mt19937_64 rng(3);
  // Where R(h)'s own palm pose puts the palm, a ball.
  robot::CollisionChecker open(test::collisionOf(panda()), scene, nullptr);
  const GraspConfigurator probe(panda(), ik, pandaHand(), open, scene.target_pose,
                                scene.robot_base);
  const HandQuery hand = pandaHand().query(pinch().positions, pinch().outward_normals);
  ASSERT_TRUE(hand.free_turn.has_value());
  scene.obstacles.push_back(ball("ball", scene.target_pose * hand.palm_pose.translation(), 0.04));
  robot::CollisionChecker checker(test::collisionOf(panda()), scene, nullptr);
  GraspConfigurator configurator(panda(), ik, pandaHand(), checker, scene.target_pose,
                                 scene.robot_base);
  EXPECT_EQ(configurator.turns(), 1);
  const GraspConfigurations one = configurator.configure(pinch(), rng);
  EXPECT_EQ(one.turns_tried, 1);
  for (const GraspConfiguration& c : one.configurations)
    EXPECT_NE(c.label, ConfigurationLabel::kCollisionFree) << "the ball is where the palm goes";

  configurator.setTurns(8);
  EXPECT_EQ(configurator.turns(), 8);
  const GraspConfigurations turned = configurator.configure(pinch(), rng);
  EXPECT_GE(turned.turns_tried, 1);
  EXPECT_LE(turned.turns_tried, 8);
  EXPECT_LE(turned.turns_blocked, turned.turns_tried - 1);
  int free = 0;
  for (const GraspConfiguration& c : turned.configurations) {
    // Every turn keeps the fingertips on the contacts.
    EXPECT_LT(fingertipDistance(turned, c, scene.target_pose), 1e-3);
    free += c.label == ConfigurationLabel::kCollisionFree;
  }
  EXPECT_GT(free, 0);
}

TEST(GraspConfigurations, WithoutTurningAGripperTakesOnlyRhsOwnPalmPose) {
  const robot::ArmIk ik(panda());
  const robot::Scene scene = freeSpace("box", {0.5, 0.0, 0.25});
  robot::CollisionChecker checker(test::collisionOf(panda()), scene, nullptr);
  GraspConfigurator configurator(panda(), ik, pandaHand(), checker, scene.target_pose,
                                 scene.robot_base);
  std::mt19937_64 a(6), b(6);
  configurator.setTurns(1);
  const GraspConfigurations one = configurator.configure(pinch(), a);
  configurator.setTurns(8);
  const GraspConfigurations unturned = configurator.configure(pinch(), b, /*turn=*/false);
  EXPECT_EQ(unturned.turns_tried, 1);
  EXPECT_EQ(unturned.turns_blocked, 0);
  ASSERT_EQ(unturned.configurations.size(), one.configurations.size());
  ASSERT_GT(one.configurations.size(), 1u);
  for (std::size_t c = 0; c < one.configurations.size(); ++c)
    EXPECT_EQ(unturned.configurations[c].grasp, one.configurations[c].grasp);
  EXPECT_EQ(a(), b()) << "no draw for a turn";
}

TEST(GraspConfigurations, AGripperBlockedAtEveryTurnStillGetsItsCollidingConfigurations) {
  const robot::ArmIk ik(panda());
  robot::Scene scene = freeSpace("box", {0.5, 0.0, 0.25});
  // A ball around the contacts: the hand meets it at every turn.
  scene.obstacles.push_back(ball("ball", scene.target_pose * Eigen::Vector3d(0, 0, 0.06), 0.2));
  robot::CollisionChecker checker(test::collisionOf(panda()), scene, nullptr);
  GraspConfigurator configurator(panda(), ik, pandaHand(), checker, scene.target_pose,
                                 scene.robot_base);
  configurator.setTurns(6);
  std::mt19937_64 rng(4);
  const GraspConfigurations all = configurator.configure(pinch(), rng);
  EXPECT_EQ(all.turns_tried, 6);
  EXPECT_EQ(all.turns_blocked, 6);
  ASSERT_FALSE(all.configurations.empty());
  for (const GraspConfiguration& c : all.configurations) {
    EXPECT_EQ(c.label, ConfigurationLabel::kColliding);
    EXPECT_EQ(c.collision.second, "obstacle 'ball'");
  }
}

TEST(GraspConfigurations, TurnsAreIgnoredByAHandThatCannotTurnFreely) {
  const HandReachability thorough(m(), handMap(), HandQueryOptions::thorough());
  const robot::ArmIk ik(m());
  const db::ObjectDatabase& box = test::bundledObjects().at("box");
  const HftsSpace space(box, 3);
  const robot::Scene scene = freeSpace("box", {0.6, 0.0, 0.15});
  robot::CollisionChecker checker(test::collisionOf(m()), scene, &box.geometry);
  GraspConfigurator configurator(m(), ik, thorough, checker, scene.target_pose, scene.robot_base);
  int solved = 0;
  for (std::uint64_t i = 0; i < 20; ++i) {
    const HftsNode node = space.child(space.root(), i * 211);
    std::mt19937_64 a(5), b(5);
    configurator.setTurns(1);
    const GraspConfigurations one = configurator.configure(space, node, a);
    configurator.setTurns(8);
    const GraspConfigurations eight = configurator.configure(space, node, b);
    EXPECT_FALSE(eight.hand.free_turn.has_value());
    EXPECT_EQ(eight.turns_tried, 1);
    ASSERT_EQ(one.configurations.size(), eight.configurations.size());
    for (std::size_t c = 0; c < one.configurations.size(); ++c)
      EXPECT_EQ(one.configurations[c].pregrasp, eight.configurations[c].pregrasp);
    EXPECT_EQ(a(), b()) << "the same random draws";
    solved += one.configurations[0].label != ConfigurationLabel::kNoKinematicSolution;
  }
  EXPECT_GT(solved, 5) << "grasps with arm IK solutions were compared";
}

TEST(GraspConfigurations, WholeTurnVariantsGetTheLabelsOfTheirBranch) {
  // The UR5e's +-360 degree joints give every IK branch up to 32 variants;
  // they are labelled once per branch. Each copied label must be the one a
  // check of the variant itself gives.
  const robot::RobotModel& ur5e = ur5eAllegro();
  const HandReachability hand(ur5e, buildHandMap(ur5e, handMapOptions(ur5e)),
                              HandQueryOptions::thorough());
  const robot::ArmIk ik(ur5e);
  robot::Scene scene;
  // A wall behind the robot: the branches whose upper arm swings back meet it.
  robot::Obstacle wall;
  wall.name = "wall";
  wall.type = robot::Obstacle::Type::kBox;
  wall.size << 0.05, 2.0, 2.0;
  wall.pose.translation() << -0.2, 0.0, 0.5;
  scene.obstacles.push_back(wall);
  robot::CollisionChecker checker(test::collisionOf(ur5e), scene, nullptr);
  GraspConfigurator configurator(ur5e, ik, hand, checker, scene.target_pose, scene.robot_base);
  // The fingertips of a grasp posture in front of the robot are the contacts.
  Eigen::VectorXd q = ur5e.home();
  q.tail(ur5e.numHandDofs()) = hand.map().configurations.row(17).transpose();
  const robot::FingertipFrames tips =
      robot::fingertipFrames(ur5e, robot::forwardKinematics(ur5e, q));
  const GraspContacts grasp{tips.positions, -tips.normals};
  std::mt19937_64 rng(3);
  const GraspConfigurations all = configurator.configure(grasp, rng);
  int copied = 0, free = 0, colliding = 0;
  for (std::size_t k = 0; k < all.configurations.size(); ++k) {
    const GraspConfiguration& c = all.configurations[k];
    ASSERT_NE(c.label, ConfigurationLabel::kNoKinematicSolution);
    const bool collides = checker.inCollision(c.pregrasp) ||
                          checker.inCollision(c.grasp, robot::CollisionRequest::grasp());
    EXPECT_EQ(c.label,
              collides ? ConfigurationLabel::kColliding : ConfigurationLabel::kCollisionFree)
        << k;
    (collides ? colliding : free) += 1;
    if (c.same_poses_as < 0) continue;
    ++copied;
    const auto twin = static_cast<std::size_t>(c.same_poses_as);
    ASSERT_LT(twin, k);
    EXPECT_LT(all.configurations[twin].same_poses_as, 0) << "a twin is a checked configuration";
    const int arm = ur5e.numArmDofs();
    EXPECT_TRUE(
        robot::differByWholeTurns(c.grasp.head(arm), all.configurations[twin].grasp.head(arm)));
    EXPECT_EQ(c.grasp.tail(ur5e.numHandDofs()),
              all.configurations[twin].grasp.tail(ur5e.numHandDofs()));
    EXPECT_EQ(c.fingertip_error, all.configurations[twin].fingertip_error);
  }
  EXPECT_LT(all.configurations.front().fingertip_error, 1e-3);
  EXPECT_GT(copied, 0);
  EXPECT_GT(free, 0);
  EXPECT_GT(colliding, 0);
}

TEST(GraspConfigurations, WithAnArmReferenceEachBranchKeepsItsVariantNearestToIt) {
  const robot::RobotModel& ur5e = ur5eAllegro();
  const HandReachability hand(ur5e, buildHandMap(ur5e, handMapOptions(ur5e)),
                              HandQueryOptions::thorough());
  const robot::ArmIk ik(ur5e);
  robot::Scene scene;
  robot::CollisionChecker checker(test::collisionOf(ur5e), scene, nullptr);
  Eigen::VectorXd q = ur5e.home();
  q.tail(ur5e.numHandDofs()) = hand.map().configurations.row(17).transpose();
  const robot::FingertipFrames tips =
      robot::fingertipFrames(ur5e, robot::forwardKinematics(ur5e, q));
  const GraspContacts grasp{tips.positions, -tips.normals};
  const int arm = ur5e.numArmDofs();
  Eigen::VectorXd reference(arm);
  reference << 1.0, -2.5, 0.5, 4.0, -5.0, 2.0;

  GraspConfigurator every(ur5e, ik, hand, checker, scene.target_pose, scene.robot_base);
  GraspConfigurator nearest(ur5e, ik, hand, checker, scene.target_pose, scene.robot_base);
  nearest.setArmReference(reference);
  std::mt19937_64 a(4), b(4);
  const GraspConfigurations all = every.configure(grasp, a);
  const GraspConfigurations kept = nearest.configure(grasp, b);
  ASSERT_FALSE(kept.configurations.empty());
  ASSERT_GT(all.configurations.size(), kept.configurations.size());
  const auto armOf = [&](const GraspConfiguration& c) -> Eigen::VectorXd {
    return c.grasp.head(arm);
  };
  // Kept: one per branch, no joint a whole turn nearer to the reference.
  for (std::size_t i = 0; i < kept.configurations.size(); ++i) {
    const Eigen::VectorXd k = armOf(kept.configurations[i]);
    for (std::size_t j = 0; j < i; ++j)
      EXPECT_FALSE(robot::differByWholeTurns(k, armOf(kept.configurations[j])));
    for (int d = 0; d < arm; ++d)
      for (const double turn : {-2 * M_PI, 2 * M_PI})
        if (k(d) + turn >= ur5e.lowerLimits()(d) && k(d) + turn <= ur5e.upperLimits()(d)) {
          EXPECT_LE(std::abs(k(d) - reference(d)), std::abs(k(d) + turn - reference(d))) << d;
        }
  }
  // Every branch is still there, labelled as before.
  for (const GraspConfiguration& c : all.configurations) {
    const auto same = std::find_if(
        kept.configurations.begin(), kept.configurations.end(),
        [&](const GraspConfiguration& k) { return robot::differByWholeTurns(armOf(k), armOf(c)); });
    ASSERT_NE(same, kept.configurations.end());
    EXPECT_EQ(same->label, c.label);
    EXPECT_NEAR(same->fingertip_error, c.fingertip_error, 1e-12);
  }
  test::expectErrorMentioning<std::invalid_argument>(
      [&] { nearest.setArmReference(Eigen::VectorXd::Zero(5)); },
      {"arm", "6 values expected, got 5"});
}

TEST(GraspConfigurations, TurnsBelowOneAreRejectedByName) {
  const robot::ArmIk ik(panda());
  robot::Scene scene;
  robot::CollisionChecker checker(test::collisionOf(panda()), scene, nullptr);
  GraspConfigurator configurator(panda(), ik, pandaHand(), checker, scene.target_pose,
                                 scene.robot_base);
  test::expectErrorMentioning<std::invalid_argument>([&] { configurator.setTurns(0); },
                                                     {"turns", "must be >= 1, got 0"});
  EXPECT_EQ(configurator.turns(), 1);
}

TEST(GraspConfigurations, OtherHandsGivenTheUsedPostureAreTheSameAsAfterItsQuery) {
  const HandReachability thorough(m(), handMap(), HandQueryOptions::thorough());
  const robot::ArmIk ik(m());
  // The box alone: the bundled objects would take seconds to build.
  const db::ObjectDatabase box = preprocess::buildObjectDatabaseFromFile(
                                     test::bundledMeshDir() / "box.stl", test::fixtureParameters())
                                     .database;
  const robot::Scene scene = freeSpace("box", {0.6, 0.0, 0.15});
  robot::CollisionChecker checker(test::collisionOf(m()), scene, &box.geometry);
  GraspConfigurator configurator(m(), ik, thorough, checker, scene.target_pose, scene.robot_base);
  const HftsSpace space(box, 3);
  int compared = 0;
  for (int child = 0; child < 60 && compared < 1; ++child) {
    const GraspContacts grasp = space.representative(
        space.child(space.child(space.child(space.root(), child % 20), child / 20), 0));
    std::mt19937_64 first(4), second(4);
    const auto queried = configurator.configureOtherHands(grasp, 0.02, first);
    const HandQuery used = configurator.configure(grasp, second, false).hand;
    std::mt19937_64 third(4);
    const auto given = configurator.configureOtherHands(grasp, used, 0.02, third);
    ASSERT_EQ(queried.size(), given.size());
    for (std::size_t k = 0; k < queried.size(); ++k) {
      EXPECT_EQ(queried[k].hand.hand_configuration, given[k].hand.hand_configuration);
      ASSERT_EQ(queried[k].configurations.size(), given[k].configurations.size());
      for (std::size_t c = 0; c < given[k].configurations.size(); ++c)
        EXPECT_EQ(queried[k].configurations[c].grasp, given[k].configurations[c].grasp);
    }
    if (!given.empty()) ++compared;
  }
  EXPECT_EQ(compared, 1) << "no grasp with other postures to compare";
}

}  // namespace
}  // namespace hfts::grasp
