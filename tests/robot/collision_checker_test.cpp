#include "robot/collision_checker.h"

#include <gtest/gtest.h>

#include <hwy/targets.h>
#include <limits>

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <thread>

#include "bundled_objects.h"
#include "core/invalid_argument.h"
#include "robot/arm_ik.h"
#include "robot/kinematics.h"
#include "robot_fixture.h"
#include "test_meshes.h"

namespace hfts::robot {
namespace {

const RobotModel& m() {
  return test::kr5Sdh();
}

const std::map<std::string, db::ObjectDatabase>& objects() {
  return test::bundledObjects();
}

Scene bundledScene(const std::string& name) {
  return loadScene(test::sourcePath("objects/scenes/" + name + ".json"));
}

const char* kScenes[] = {"table", "shelf", "bin"};

/// Calls check(scene, object database, checker) with every bundled object
/// standing at the target pose of every bundled scene (on its support).
template <typename Check>
void forEveryObjectInEveryScene(Check check) {
  for (const char* name : kScenes) {
    Scene scene = bundledScene(name);
    for (const auto& [object, db] : objects()) {
      SCOPED_TRACE(std::string(name) + " / " + object);
      scene.target_object = object;
      scene.target_pose = targetPose(scene, db.geometry.mesh_vertices);
      CollisionChecker checker(test::collisionOf(m()), scene, &db.geometry);
      check(scene, db, checker);
    }
  }
}

TEST(CollisionChecker, EveryBundledObjectFitsEveryPlacementOfEveryScene) {
  // The placements an object does not fit (docs/scenes.md): the basin,
  // 19.5 cm across, is too wide for the bin's corner.
  const std::set<std::string> misfits = {"bin/corner/basin"};
  int placements = 0;
  for (const char* name : kScenes) {
    const Scene scene = bundledScene(name);
    EXPECT_GE(scene.placements.size(), 2u) << name;  // with the target's: at least three
    std::vector<std::string> names = {"target"};
    for (const Placement& p : scene.placements) names.push_back(p.name);
    for (const std::string& placement : names) {
      ++placements;
      for (const auto& [object, db] : objects()) {
        const std::string where = std::string(name) + "/" + placement + "/" + object;
        SCOPED_TRACE(where);
        Scene placed = scene.withPlacement(placement);
        placed.target_object = object;
        placed.target_pose = targetPose(placed, db.geometry.mesh_vertices);
        CollisionChecker checker(test::collisionOf(m()), placed, &db.geometry);
        CollisionPair pair;
        EXPECT_EQ(checker.scene().targetTouchesObstacles(&pair), misfits.count(where) == 1)
            << pair.first << " / " << pair.second;
        const Eigen::VectorXd start = placed.startFor(m().name()).value_or(m().home());
        EXPECT_FALSE(checker.inCollision(start, &pair)) << pair.first << " / " << pair.second;
        EXPECT_GT(checker.clearance(start), 0.0);  // the base stands 1 mm above the table
      }
    }
  }
  EXPECT_EQ(placements, 9);
}

/// Palm poses around the object: palm z pointing at the object's centre
/// from above and from the sides, the palm `standoff` from the centre.
std::vector<Eigen::Isometry3d> approaches(const Scene& scene, const db::ObjectGeometry& g,
                                          double standoff) {
  const Eigen::Vector3d centre = scene.target_pose * (0.5 * (g.bbox_min + g.bbox_max));
  std::vector<Eigen::Isometry3d> out;
  for (int elevation = 0; elevation <= 90; elevation += 15) {
    for (int azimuth = 0; azimuth < 360; azimuth += 20) {
      const double el = elevation * M_PI / 180, az = azimuth * M_PI / 180;
      const Eigen::Vector3d from(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                                 std::sin(el));
      for (double roll = 0; roll < M_PI; roll += M_PI / 4) {
        Eigen::Isometry3d palm = Eigen::Isometry3d::Identity();
        const Eigen::Vector3d z = -from;
        const Eigen::Vector3d x = z.unitOrthogonal();
        palm.linear().col(0) = Eigen::AngleAxisd(roll, z) * x;
        palm.linear().col(2) = z;
        palm.linear().col(1) = z.cross(palm.linear().col(0));
        palm.translation() = centre + standoff * from;
        out.push_back(scene.robot_base.inverse() * palm);
      }
    }
  }
  return out;
}

TEST(CollisionChecker, EveryObjectIsWithinReachInEveryScene) {
  const ArmIk ik(m());
  std::mt19937_64 rng(1);
  forEveryObjectInEveryScene(
      [&](const Scene& scene, const db::ObjectDatabase& db, CollisionChecker& checker) {
        const double radius = 0.5 * (db.geometry.bbox_max - db.geometry.bbox_min).norm();
        int free = 0, reachable = 0, tried = 0;
        for (const Eigen::Isometry3d& palm : approaches(scene, db.geometry, radius + 0.24)) {
          ++tried;
          const auto solutions = ik.solvePalm(palm, rng);
          reachable += !solutions.empty();
          for (const Eigen::VectorXd& arm : solutions) {
            Eigen::VectorXd q(13);
            q << arm, m().handOpen();
            if (!checker.inCollision(q)) {
              ++free;
              break;
            }
          }
        }
        EXPECT_GT(reachable, tried / 4);
        EXPECT_GT(free, 0);
        // Cluttered: many approaches are blocked.
        EXPECT_LT(free, reachable);
      });
}

TEST(CollisionChecker, PalmInsideTheTargetCollidesInEveryScene) {
  const ArmIk ik(m());
  std::mt19937_64 rng(2);
  for (const char* name : kScenes) {
    SCOPED_TRACE(name);
    const Scene scene = bundledScene(name);
    const db::ObjectDatabase& target = objects().at(scene.target_object);
    CollisionChecker checker(test::collisionOf(m()), scene, &target.geometry);
    // The palm, pointing down, at the middle of the object's bounding box.
    Eigen::Isometry3d palm = Eigen::Isometry3d::Identity();
    palm.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
    palm.translation() = scene.robot_base.inverse() * scene.target_pose *
                         (0.5 * (target.geometry.bbox_min + target.geometry.bbox_max));
    const auto solutions = ik.solvePalm(palm, rng);
    ASSERT_FALSE(solutions.empty());
    for (const Eigen::VectorXd& arm : solutions) {
      Eigen::VectorXd q(13);
      q << arm, m().handOpen();
      CollisionPair pair;
      EXPECT_TRUE(checker.inCollision(q, &pair));
      EXPECT_DOUBLE_EQ(checker.clearance(q), 0.0);
    }
  }
}

TEST(CollisionChecker, FoldedArmCollidesWithItself) {
  Scene empty;
  CollisionChecker checker(test::collisionOf(m()), empty, nullptr);
  Eigen::VectorXd q = m().home();
  EXPECT_FALSE(checker.inCollision(q));
  q(2) = m().upperLimits()(2);  // fold the forearm back down onto the robot
  CollisionPair pair;
  ASSERT_TRUE(checker.inCollision(q, &pair));
  EXPECT_GE(m().linkIndex(pair.first), 0);
  EXPECT_GE(m().linkIndex(pair.second), 0);
}

/// A 1 cm cube object placed at a point of the world.
db::ObjectGeometry smallCube() {
  return test::meshObject(test::cube(0.01));
}

/// The small cube with a face on fingertip `tip`'s pad at q, moved `depth`
/// m into the pad along its normal.
Scene cubeInPad(const Eigen::VectorXd& q, Eigen::Index tip, double depth) {
  const FingertipFrames tips = fingertipFrames(m(), forwardKinematics(m(), q));
  const Eigen::Vector3d normal = tips.normals.col(tip);
  Scene scene;
  scene.target_object = "cube";
  scene.target_pose.linear() =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), normal).toRotationMatrix();
  scene.target_pose.translation() = tips.positions.col(tip) + (0.005 - depth) * normal;
  return scene;
}

TEST(CollisionChecker, OnlyFingertipsMayTouchTheTargetUnderTheGraspRule) {
  const Eigen::VectorXd q = m().home();
  const db::ObjectGeometry cube = smallCube();
  Scene scene = cubeInPad(q, 0, 0.0005);
  CollisionChecker touching(test::collisionOf(m()), scene, &cube);
  CollisionPair pair;
  EXPECT_TRUE(touching.inCollision(q, &pair));
  EXPECT_FALSE(touching.inCollision(q, CollisionRequest::grasp(), &pair)) << pair.first;

  const LinkPoses poses = forwardKinematics(m(), q);
  scene.target_pose.translation() =
      poses[static_cast<std::size_t>(m().palmLink())] * Eigen::Vector3d(0, 0, 0.04);
  CollisionChecker palm(test::collisionOf(m()), scene, &cube);
  EXPECT_TRUE(palm.inCollision(q, CollisionRequest::grasp(), &pair));
  EXPECT_EQ(pair.second.find("target"), 0u) << pair.first << " / " << pair.second;
}

TEST(CollisionChecker, AFingertipDeeperThanMaxPenetrationCollidesUnderTheGraspRule) {
  const Eigen::VectorXd q = m().home();
  const db::ObjectGeometry cube = smallCube();
  // The pad 3 mm in: rejected at the default 1 mm, allowed at 4 mm.
  CollisionChecker deep(test::collisionOf(m()), cubeInPad(q, 1, 0.003), &cube);
  EXPECT_DOUBLE_EQ(deep.maxPenetration(), kDefaultMaxPenetration);
  CollisionPair pair;
  EXPECT_TRUE(deep.inCollision(q, CollisionRequest::grasp(), &pair));
  EXPECT_EQ(pair.first, m().links()[static_cast<std::size_t>(m().fingertips()[1].link)].name);
  EXPECT_EQ(pair.second, "target 'cube'");
  deep.setMaxPenetration(0.004);
  EXPECT_FALSE(deep.inCollision(q, CollisionRequest::grasp()));
  // Either side of the default by a tenth of a millimetre.
  EXPECT_FALSE(CollisionChecker(test::collisionOf(m()), cubeInPad(q, 1, 0.0009), &cube)
                   .inCollision(q, CollisionRequest::grasp()));
  EXPECT_TRUE(CollisionChecker(test::collisionOf(m()), cubeInPad(q, 1, 0.0011), &cube)
                  .inCollision(q, CollisionRequest::grasp()));
  EXPECT_THROW(deep.setMaxPenetration(-1e-3), hfts::InvalidArgument);
}

/// A thin wall in the plane y = 0 in front of the robot, alone in a scene.
Scene wallInFront() {
  Scene scene;
  Obstacle wall;
  wall.name = "wall";
  wall.size << 0.6, 0.01, 0.5;
  wall.pose.translation() << 0.6, 0.0, 0.5;
  scene.obstacles.push_back(wall);
  return scene;
}

/// wallInFront() with a target at (0.5, 0.2, 0.4) (a smallCube()).
Scene wallAndTarget() {
  Scene scene = wallInFront();
  scene.target_pose.translation() << 0.5, 0.2, 0.4;
  return scene;
}

/// A random configuration within the limits, its palm pose (world frame)
/// and its hand joints.
struct PlacedHand {
  Eigen::VectorXd q;
  Eigen::Isometry3d palm;
  Eigen::VectorXd hand;
};

PlacedHand randomPlacedHand(const Scene& scene, std::mt19937_64& rng) {
  Eigen::VectorXd q(m().numDofs());
  for (int j = 0; j < q.size(); ++j)
    q(j) = std::uniform_real_distribution<double>(m().lowerLimits()(j), m().upperLimits()(j))(rng);
  const Eigen::Isometry3d palm =
      scene.robot_base * forwardKinematics(m(), q)[static_cast<std::size_t>(m().palmLink())];
  return {q, palm, q.tail(m().numHandDofs())};
}

TEST(CollisionChecker, TheHandAloneCollidesWhereTheWholeRobotsHandDoes) {
  // A wall in front of the robot and a cube target: random configurations
  // near them. Where the whole robot is free, the hand alone at the same
  // palm pose is too; where the robot's first contact is a hand link with
  // the wall, the hand alone meets the wall.
  const Scene scene = wallAndTarget();
  const db::ObjectGeometry cube = smallCube();
  CollisionChecker checker(test::collisionOf(m()), scene, &cube);
  std::mt19937_64 rng(4);
  int free = 0, handOnWall = 0;
  for (int i = 0; i < 4000; ++i) {
    const auto [q, palm, hand] = randomPlacedHand(scene, rng);
    CollisionPair pair;
    if (!checker.inCollision(q, &pair)) {
      ++free;
      EXPECT_FALSE(checker.handInCollision(palm, hand, CollisionRequest::obstaclesOnly()));
    } else if (pair.second == "obstacle 'wall'" && m().isHandLink(m().linkIndex(pair.first))) {
      ++handOnWall;
      CollisionPair handPair;
      EXPECT_TRUE(checker.handInCollision(palm, hand, CollisionRequest::obstaclesOnly(), &handPair))
          << pair.first;
      EXPECT_EQ(handPair.second, "obstacle 'wall'");
      EXPECT_TRUE(m().isHandLink(m().linkIndex(handPair.first))) << handPair.first;
    }
  }
  EXPECT_GT(free, 100);
  EXPECT_GT(handOnWall, 20);

  // The target object is not an obstacle: the palm inside it is clear.
  Eigen::Isometry3d inTarget = scene.target_pose;
  EXPECT_FALSE(
      checker.handInCollision(inTarget, m().handOpen(), CollisionRequest::obstaclesOnly()));
  inTarget.translation() = scene.obstacles.front().pose.translation();
  EXPECT_TRUE(checker.handInCollision(inTarget, m().handOpen(), CollisionRequest::obstaclesOnly()));
  EXPECT_THROW(checker.handInCollision(inTarget, Eigen::VectorXd::Zero(2),
                                       CollisionRequest::obstaclesOnly()),
               std::invalid_argument);
}

TEST(CollisionChecker, TheHandAloneMeetsTheTargetUnderEitherRule) {
  // As OnlyFingertipsMayTouchTheTargetUnderTheGraspRule, with the hand
  // alone at the home configuration's palm pose.
  const Eigen::VectorXd q = m().home();
  const LinkPoses poses = forwardKinematics(m(), q);
  const Eigen::Isometry3d palm = poses[static_cast<std::size_t>(m().palmLink())];
  const Eigen::VectorXd hand = q.tail(m().numHandDofs());
  const db::ObjectGeometry cube = smallCube();
  Scene scene = cubeInPad(q, 0, 0.0005);
  CollisionChecker touching(test::collisionOf(m()), scene, &cube);
  CollisionPair pair;
  EXPECT_TRUE(touching.handInCollision(palm, hand, CollisionRequest{}, &pair));
  EXPECT_EQ(pair.second, "target 'cube'");
  EXPECT_EQ(pair.first, m().links()[static_cast<std::size_t>(m().fingertips()[0].link)].name);
  EXPECT_FALSE(touching.handInCollision(palm, hand, CollisionRequest::grasp()));
  EXPECT_FALSE(touching.handInCollision(
      palm, hand, CollisionRequest::obstaclesOnly()));  // the target is no obstacle

  scene.target_pose.translation() = palm * Eigen::Vector3d(0, 0, 0.04);
  CollisionChecker inPalm(test::collisionOf(m()), scene, &cube);
  EXPECT_TRUE(inPalm.handInCollision(palm, hand, CollisionRequest::grasp(), &pair));
  EXPECT_EQ(pair.second, "target 'cube'");
  EXPECT_TRUE(m().isHandLink(m().linkIndex(pair.first))) << pair.first;
  Eigen::Isometry3d away = palm;
  away.translation().z() += 2.0;
  EXPECT_FALSE(inPalm.handInCollision(away, hand, CollisionRequest{}));
  EXPECT_THROW(inPalm.handInCollision(palm, Eigen::VectorXd::Zero(1), CollisionRequest::grasp()),
               std::invalid_argument);
}

TEST(CollisionChecker, WhereTheWholeRobotIsFreeTheHandAloneIsFreeToo) {
  // The hand's links and pairs are some of the robot's: on random
  // configurations near a wall and a target, a free robot has a free hand
  // under the same rule, and a colliding hand a colliding robot.
  const Scene scene = wallAndTarget();
  const db::ObjectGeometry cube = smallCube();
  CollisionChecker checker(test::collisionOf(m()), scene, &cube);
  std::mt19937_64 rng(5);
  int handCollides = 0;
  for (int i = 0; i < 3000; ++i) {
    const auto [q, palm, hand] = randomPlacedHand(scene, rng);
    for (const bool grasp : {false, true}) {
      const bool robot =
          grasp ? checker.inCollision(q, CollisionRequest::grasp()) : checker.inCollision(q);
      const bool alone = checker.handInCollision(
          palm, hand, grasp ? CollisionRequest::grasp() : CollisionRequest{});
      if (!robot) {
        EXPECT_FALSE(alone) << i;
      }
      if (alone) {
        EXPECT_TRUE(robot) << i;
        ++handCollides;
      }
    }
  }
  EXPECT_GT(handCollides, 20);
}

TEST(CollisionChecker, ASharedCollisionMeshGivesTheSameAnswersFromAnyThread) {
  // Random configurations around a palm-down pose over the mug (alone in
  // the scene): some touch it.
  Scene scene;
  scene.target_object = "mug";
  scene.target_pose = bundledScene("table").target_pose;
  const db::ObjectDatabase& mug = objects().at("mug");
  const CollisionMesh shared(TriangleMesh{mug.geometry.mesh_vertices, mug.geometry.mesh_triangles});
  const ArmIk ik(m());
  std::mt19937_64 rng(5);
  Eigen::Isometry3d palm = Eigen::Isometry3d::Identity();
  palm.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  palm.translation() = scene.robot_base.inverse() * scene.target_pose * Eigen::Vector3d(0, 0, 0.34);
  const auto solutions = ik.solvePalm(palm, rng);
  ASSERT_FALSE(solutions.empty());
  std::vector<Eigen::VectorXd> qs;
  std::normal_distribution<double> noise(0.0, 0.05);
  for (int i = 0; i < 200; ++i) {
    Eigen::VectorXd q(13);
    q << solutions.front(), m().handOpen();
    for (Eigen::Index d = 0; d < 6; ++d) q(d) += noise(rng);
    qs.push_back(q);
  }
  CollisionChecker own(test::collisionOf(m()), scene, &mug.geometry);
  std::vector<char> expected;
  for (const Eigen::VectorXd& q : qs) expected.push_back(own.inCollision(q) ? 1 : 0);
  const auto hits = std::count(expected.begin(), expected.end(), 1);
  ASSERT_GT(hits, 20);
  ASSERT_LT(hits, 180);
  // Four threads, each with its own checker on the one hierarchy.
  std::vector<std::vector<char>> answers(4);
  std::vector<std::thread> threads;
  for (auto& out : answers)
    threads.emplace_back([&, out = &out] {
      CollisionChecker checker(test::collisionOf(m()), scene, &mug.geometry, &shared);
      for (int round = 0; round < 3; ++round) {
        out->clear();
        for (const Eigen::VectorXd& q : qs) out->push_back(checker.inCollision(q) ? 1 : 0);
      }
    });
  for (std::thread& t : threads) t.join();
  for (const auto& out : answers) EXPECT_EQ(out, expected);

  // Four threads, each with its own checker over one scene (as racing
  // plans share it), under both rules and with both tiers.
  const auto scenePrepared =
      std::make_shared<const CollisionScene>(test::collisionOf(m()), scene, &mug.geometry, &shared);
  std::vector<char> expectedGrasp;
  for (const Eigen::VectorXd& q : qs)
    expectedGrasp.push_back(own.inCollision(q, CollisionRequest::grasp()) ? 1 : 0);
  ASSERT_NE(expectedGrasp, expected);  // some fingertip contacts the grasp rule allows
  std::vector<std::vector<char>> strict(4), grasp(4);
  threads.clear();
  for (std::size_t i = 0; i < strict.size(); ++i)
    threads.emplace_back([&, i] {
      CollisionChecker checker(scenePrepared);
      checker.setSphereTier(i % 2 == 0);
      for (const Eigen::VectorXd& q : qs) {
        strict[i].push_back(checker.inCollision(q) ? 1 : 0);
        grasp[i].push_back(checker.inCollision(q, CollisionRequest::grasp()) ? 1 : 0);
      }
    });
  for (std::thread& t : threads) t.join();
  for (std::size_t i = 0; i < strict.size(); ++i) {
    EXPECT_EQ(strict[i], expected) << i;
    EXPECT_EQ(grasp[i], expectedGrasp) << i;
  }
}

// What a request leaves out is never a collision, with or without the
// sphere tier; what it names still is.
TEST(CollisionChecker, ACheckerWithoutASceneIsRefusedByName) {
  test::expectErrorMentioning<InvalidArgument>([] { CollisionChecker checker(nullptr); },
                                               {"scene", "collision scene"});
}

TEST(CollisionChecker, ARequestCountsOnlyWhatItNames) {
  for (const bool tier : {true, false}) {
    SCOPED_TRACE(tier ? "two tiers" : "FCL only");
    CollisionChecker empty(test::collisionOf(m()), Scene{}, nullptr);
    empty.setSphereTier(tier);
    Eigen::VectorXd folded = m().home();
    folded(2) = m().upperLimits()(2);  // the forearm folded onto the robot
    CollisionRequest noSelf;
    noSelf.self = false;
    EXPECT_TRUE(empty.inCollision(folded));
    EXPECT_FALSE(empty.inCollision(folded, noSelf));

    // A 10 cm cube target around the palm.
    const db::ObjectGeometry cube = test::meshObject(test::cube(0.1));
    Scene scene;
    scene.target_object = "cube";
    scene.target_pose.translation() =
        forwardKinematics(m(), m().home())[static_cast<std::size_t>(m().palmLink())].translation();
    CollisionChecker inTarget(test::collisionOf(m()), scene, &cube);
    inTarget.setSphereTier(tier);
    CollisionPair pair;
    ASSERT_TRUE(inTarget.inCollision(m().home(), &pair));
    EXPECT_EQ(pair.second, "target 'cube'");
    CollisionRequest noTarget;
    noTarget.target = false;
    EXPECT_FALSE(inTarget.inCollision(m().home(), noTarget));
    EXPECT_FALSE(inTarget.inCollision(m().home(), CollisionRequest::obstaclesOnly()));
    // Turning joint 1 sweeps the hand through the wall: the obstacle counts
    // without the target.
    CollisionChecker wall(test::collisionOf(m()), wallInFront(), nullptr);
    wall.setSphereTier(tier);
    Eigen::VectorXd a = m().home(), b = m().home();
    a(0) = 0.8;
    b(0) = -0.8;
    EXPECT_FALSE(wall.isMotionValid(a, b, 0.01, noTarget, &pair));
    EXPECT_EQ(pair.second, "obstacle 'wall'");
    // ... and the target without the obstacles.
    EXPECT_TRUE(wall.isMotionValid(a, b, 0.01, CollisionRequest::targetOnly()));
    EXPECT_TRUE(inTarget.inCollision(m().home(), CollisionRequest::targetOnly()));
    // Distances alike: to the target only, to the obstacles only (none).
    std::vector<double> d;
    const int palm = m().palmLink();
    inTarget.linkClearances(m().home(), {palm}, d, CollisionRequest::targetOnly());
    EXPECT_EQ(d.at(0), 0.0);
    inTarget.linkClearances(m().home(), {palm}, d, CollisionRequest::obstaclesOnly());
    EXPECT_EQ(d.at(0), std::numeric_limits<double>::infinity());
    // A mesh beyond exactWithin of its box counts with the box's distance:
    // a lower bound, exact within.
    std::vector<double> exact, bounded;
    inTarget.linkClearances(a, {palm}, exact, CollisionRequest::targetOnly());
    ASSERT_GT(exact.at(0), 0.05);
    inTarget.linkClearances(a, {palm}, bounded, CollisionRequest::targetOnly(), 0.01);
    EXPECT_LE(bounded.at(0), exact.at(0) + 1e-6);  // the solvers round differently
    EXPECT_GE(bounded.at(0), 0.01);
    inTarget.linkClearances(a, {palm}, bounded, CollisionRequest::targetOnly(), 10.0);
    EXPECT_EQ(bounded.at(0), exact.at(0));
    wall.linkClearances(a, {palm}, d, CollisionRequest::targetOnly());
    EXPECT_EQ(d.at(0), std::numeric_limits<double>::infinity());
    wall.linkClearances(a, {palm}, d, CollisionRequest::obstaclesOnly());
    EXPECT_GT(d.at(0), 0.0);
    EXPECT_LT(d.at(0), 1.0);
  }
}

TEST(CollisionChecker, MotionIsCheckedAtTheGivenResolution) {
  // Turning joint 1 from one side of the wall to the other sweeps the hand
  // through it.
  CollisionChecker checker(test::collisionOf(m()), wallInFront(), nullptr);
  Eigen::VectorXd a = m().home(), b = m().home();
  a(0) = 0.8;
  b(0) = -0.8;
  ASSERT_FALSE(checker.inCollision(a));
  ASSERT_FALSE(checker.inCollision(b));
  CollisionPair pair;
  EXPECT_FALSE(checker.isMotionValid(a, b, 0.01, CollisionRequest{}, &pair));
  EXPECT_EQ(pair.second, "obstacle 'wall'");
  EXPECT_TRUE(checker.isMotionValid(a, b, 10.0));  // one step: only the end is checked
  EXPECT_NEAR(checker.metric().distance(a, b), 1.6, 1e-12);
  EXPECT_THROW(checker.isMotionValid(a, b, 0.0), std::invalid_argument);
}

/// A uniformly random configuration within the limits.
Eigen::VectorXd randomConfiguration(std::mt19937_64& rng) {
  Eigen::VectorXd q(m().numDofs());
  for (int d = 0; d < m().numDofs(); ++d)
    q(d) = std::uniform_real_distribution<double>(m().lowerLimits()(d), m().upperLimits()(d))(rng);
  return q;
}

/// Whether every state a + (b - a) k / n, k = 1..n, n = ceil(d / resolution)
/// is free, checked one by one.
bool everyStateFree(CollisionChecker& checker, const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                    double resolution) {
  const int n =
      std::max(1, static_cast<int>(std::ceil(checker.metric().distance(a, b) / resolution)));
  for (int k = 1; k <= n; ++k)
    if (checker.inCollision(a + (b - a) * (static_cast<double>(k) / n))) return false;
  return true;
}

TEST(CollisionChecker, AMotionChecksEveryStateOfItsSegment) {
  // Segments from free configurations in the shelf scene, 0.3 and 2 rad
  // long, at 0.02 and 0.0018 (up to 1,112 steps, past the 1,024 whose
  // check order the checker keeps): isMotionValid is the one-by-one check
  // of their states; a polyline of them is free up to its first segment
  // that is not.
  Scene scene = bundledScene("shelf");
  const db::ObjectDatabase& db = objects().at(scene.target_object);
  for (const bool spheres : {true, false}) {
    SCOPED_TRACE(spheres ? "two tiers" : "FCL only");
    CollisionChecker checker(test::collisionOf(m()), scene, &db.geometry);
    checker.setSphereTier(spheres);
    std::mt19937_64 rng(17);
    const auto stepFrom = [&](const Eigen::VectorXd& a, double length) {
      const Eigen::VectorXd toward = randomConfiguration(rng) - a;
      return Eigen::VectorXd(a + toward * (length / checker.metric().distance(toward, 0 * toward)));
    };
    int free = 0, colliding = 0;
    for (int i = 0; i < 16; ++i) {
      Eigen::VectorXd a = randomConfiguration(rng);
      while (checker.inCollision(a)) a = randomConfiguration(rng);
      const Eigen::VectorXd b = stepFrom(a, i % 2 == 0 ? 0.3 : 2.0);
      const double resolution = i % 3 == 0 ? 0.0018 : 0.02;
      const bool expected = everyStateFree(checker, a, b, resolution);
      EXPECT_EQ(checker.isMotionValid(a, b, resolution), expected) << i;
      (expected ? free : colliding) += 1;
    }
    EXPECT_GT(free, 3);
    EXPECT_GT(colliding, 3);
    std::size_t partial = 0;
    for (int walk = 0; walk < 30; ++walk) {
      std::vector<Eigen::VectorXd> line{randomConfiguration(rng)};
      while (checker.inCollision(line.front())) line.front() = randomConfiguration(rng);
      for (int step = 0; step < 8; ++step) line.push_back(stepFrom(line.back(), 0.5));
      std::size_t expected = 0;
      while (expected + 1 < line.size() &&
             everyStateFree(checker, line[expected], line[expected + 1], 0.02))
        ++expected;
      EXPECT_EQ(checker.validSegments(line, 0.02), expected) << walk;
      partial += expected > 0 && expected + 1 < line.size();
    }
    EXPECT_GT(partial, 2u);
  }
  CollisionChecker checker(test::collisionOf(m()), scene, nullptr);
  test::expectErrorMentioning<InvalidArgument>(
      [&] {
        checker.validSegments({m().home(), Eigen::VectorXd::Zero(3)}, 0.02);
      },
      {"waypoints", "waypoint 1 has 3 values"});
}

TEST(CollisionChecker, ValidSegmentsIsIsMotionValidSegmentBySegment) {
  // Random walks of 0.3-rad steps (many end in a collision somewhere), in
  // one stream and one segment at a time: the same count of valid leading
  // segments and the same number of checked states, with the sphere tier
  // and without.
  Scene scene = bundledScene("shelf");
  const db::ObjectDatabase& db = objects().at(scene.target_object);
  for (const bool spheres : {true, false}) {
    CollisionChecker stream(test::collisionOf(m()), scene, &db.geometry),
        oneByOne(test::collisionOf(m()), scene, &db.geometry);
    stream.setSphereTier(spheres);
    oneByOne.setSphereTier(spheres);
    std::mt19937_64 rng(9);
    std::size_t partial = 0;
    for (int walk = 0; walk < 60; ++walk) {
      std::vector<Eigen::VectorXd> line{randomConfiguration(rng)};
      while (oneByOne.inCollision(line.front())) line.front() = randomConfiguration(rng);
      const std::uint64_t streamBefore = stream.checkCount(), oneBefore = oneByOne.checkCount();
      for (int step = 0; step < 8; ++step) {
        const Eigen::VectorXd toward = randomConfiguration(rng) - line.back();
        const double length =
            oneByOne.metric().distance(toward, Eigen::VectorXd::Zero(toward.size()));
        line.push_back(line.back() + toward * (0.3 / length));
      }
      std::size_t expected = 0;
      while (expected + 1 < line.size() &&
             oneByOne.isMotionValid(line[expected], line[expected + 1], 0.02))
        ++expected;
      EXPECT_EQ(stream.validSegments(line, 0.02), expected) << walk;
      EXPECT_EQ(stream.checkCount() - streamBefore, oneByOne.checkCount() - oneBefore) << walk;
      partial += expected > 0 && expected < line.size() - 1;
    }
    EXPECT_GT(partial, 5u);  // walks that end in a collision after some free steps
  }
  CollisionChecker checker(test::collisionOf(m()), scene, nullptr);
  EXPECT_EQ(checker.validSegments({m().home()}, 0.02), 0u);
  EXPECT_THROW(checker.validSegments({m().home(), m().home()}, 0.0), std::invalid_argument);
}

/// Both rules with the sphere tier and without; returns whether q collides
/// (without the grasp rule). Counts the answers the tier settled alone.
bool expectSameAnswerWithAndWithoutSpheres(CollisionChecker& checker, const Eigen::VectorXd& q) {
  checker.setSphereTier(false);
  const bool exact = checker.inCollision(q);
  const bool exactGrasp = checker.inCollision(q, CollisionRequest::grasp());
  checker.setSphereTier(true);
  EXPECT_EQ(checker.inCollision(q), exact) << q.transpose();
  EXPECT_EQ(checker.inCollision(q, CollisionRequest::grasp()), exactGrasp) << q.transpose();
  return exact;
}

TEST(CollisionChecker, TheSphereTierNeverChangesAnAnswer) {
  const ArmIk ik(m());
  std::mt19937_64 rng(3);
  std::uint64_t configurations = 0, settled = 0, collisions = 0;
  forEveryObjectInEveryScene(
      [&](const Scene& scene, const db::ObjectDatabase& db, CollisionChecker& checker) {
        EXPECT_TRUE(checker.sphereTier());  // the default
        for (int i = 0; i < 100; ++i)
          collisions += expectSameAnswerWithAndWithoutSpheres(checker, randomConfiguration(rng));
        // The open or half-closed hand around the object, where fingertips
        // touch it and spheres touch everything near it.
        const double radius = 0.5 * (db.geometry.bbox_max - db.geometry.bbox_min).norm();
        const auto palms = approaches(scene, db.geometry, radius + 0.1);
        for (std::size_t p = 0; p < palms.size(); p += 7)
          for (const Eigen::VectorXd& arm : ik.solvePalm(palms[p], rng)) {
            Eigen::VectorXd q = randomConfiguration(rng);
            q.head(m().numArmDofs()) = arm;
            collisions += expectSameAnswerWithAndWithoutSpheres(checker, q);
          }
        configurations += checker.checkCount() / 4;  // two rules, with and without spheres
        settled += checker.sphereSettledCount();
      });
  // The comparison means something: both answers occur, and the tier
  // settles some of the free configurations without FCL.
  EXPECT_GT(collisions, configurations / 10);
  EXPECT_LT(collisions, configurations * 19 / 20);
  EXPECT_GT(settled, (configurations - collisions) / 10)
      << configurations << " configurations, " << collisions << " colliding";
}

TEST(CollisionChecker, EverySimdTargetOfTheSphereTierGivesFclsAnswers) {
  // The kernel is compiled for every SIMD target (scalar, SSE, AVX2,
  // AVX-512) and runs the best one the CPU has; each must agree with FCL.
  // Single configurations only: the batch kernel's lane count
  // (kernel::batchSize()) is fixed for the process at its first use.
  Scene scene = bundledScene("shelf");
  const auto& [object, db] = *objects().begin();
  scene.target_object = object;
  scene.target_pose = targetPose(scene, db.geometry.mesh_vertices);
  const std::vector<std::int64_t> targets = hwy::SupportedAndGeneratedTargets();
  EXPECT_GE(targets.size(), 2u);  // at least the scalar fallback and one SIMD target
  for (const std::int64_t target : targets) {
    SCOPED_TRACE(hwy::TargetName(target));
    hwy::SetSupportedTargetsForTest(target);
    CollisionChecker checker(test::collisionOf(m()), scene, &db.geometry);
    std::mt19937_64 rng(5);
    int collisions = 0;
    for (int i = 0; i < 300; ++i)
      collisions += expectSameAnswerWithAndWithoutSpheres(checker, randomConfiguration(rng));
    EXPECT_GT(collisions, 30);
    EXPECT_LT(collisions, 270);
    EXPECT_GT(checker.sphereSettledCount(), 10u);
  }
  hwy::SetSupportedTargetsForTest(0);  // back to what the CPU supports
}

TEST(CollisionChecker, ExactlyTouchingLinksGetOneAnswerInBothModes) {
  // Link 4's and link 6's cylinders at distance 0: FCL's narrowphase says
  // "collision" in one argument order and "free" in the other (found by
  // bench/collision_agreement); both modes must ask it the same way.
  Eigen::VectorXd q(13);
  q << 2.3215106129252714, -1.8594253221353245, 2.0825420809148532, 1.5639640829159576,
      1.8755949620002648, 3.6333845305284154, 0.61800144603921836, -0.040445903956752405,
      0.19087458258705636, -0.9426861415550678, -1.3818885612777543, -0.48444490836207343,
      -0.0057277821734924572;
  CollisionChecker checker(test::collisionOf(m()), Scene{}, nullptr);
  CollisionPair withSpheres, fclOnly;
  const bool a = checker.inCollision(q, &withSpheres);
  checker.setSphereTier(false);
  EXPECT_EQ(checker.inCollision(q, &fclOnly), a);
  EXPECT_EQ(withSpheres.first + withSpheres.second, fclOnly.first + fclOnly.second);
}

TEST(CollisionChecker, TheSphereTierKeepsTheGraspRuleForFingertipsTouchingTheTarget) {
  const db::ObjectGeometry cube = smallCube();
  std::mt19937_64 rng(4);
  int allowed = 0;
  for (int i = 0; i < 300; ++i) {
    const Eigen::VectorXd q = randomConfiguration(rng);
    // A fingertip's pad 0.5 mm into the cube: allowed where nothing else
    // touches it.
    CollisionChecker checker(test::collisionOf(m()), cubeInPad(q, i % 3, 0.0005), &cube);
    const bool collides = expectSameAnswerWithAndWithoutSpheres(checker, q);
    allowed += collides && !checker.inCollision(q, CollisionRequest::grasp());
  }
  EXPECT_GT(allowed, 50);
}

}  // namespace
}  // namespace hfts::robot
