// A held body (RobotModel::withHeldBody, robot::withHeldBody): it moves
// with the palm, collides with the obstacles and the arm in both tiers,
// never with the hand that holds it, and the segments it sweeps are
// checked and certified with it.
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <string>

#include "core/invalid_argument.h"
#include "robot/collision_checker.h"
#include "robot/collision_model.h"
#include "robot/kinematics.h"
#include "robot/link_spheres.h"
#include "robot/motion_bound.h"
#include "robot_fixture.h"
#include "test_meshes.h"

namespace hfts::robot {
namespace {

const CollisionModel& base() {
  return test::collisionOf(test::kr5Sdh());
}

/// A 6 cm cube held `ahead` metres in front of the palm (along its z, out
/// of the hand).
std::shared_ptr<const CollisionModel> holdingCube(double ahead, double size = 0.06) {
  Eigen::Isometry3d inPalm = Eigen::Isometry3d::Identity();
  inPalm.translation() = Eigen::Vector3d(0, 0, ahead);
  return withHeldBody(base(), "cube", inPalm,
                      std::make_shared<const TriangleMesh>(test::cube(size)));
}

Eigen::VectorXd home() {
  return test::kr5Sdh().home();
}

/// The held cube's centre and its palm frame in the world at q (base at
/// the origin).
Eigen::Isometry3d heldPose(const CollisionModel& held, const Eigen::VectorXd& q) {
  return forwardKinematics(held.robot, q)[static_cast<std::size_t>(held.robot.heldLink())];
}

/// A thin plate through the held cube's centre at q, across the palm's
/// x axis: it cuts the cube's surface but lies clear of the robot.
Scene plateThroughHeld(const CollisionModel& held, const Eigen::VectorXd& q) {
  Scene scene;
  Obstacle plate;
  plate.name = "plate";
  plate.type = Obstacle::Type::kBox;
  plate.size = Eigen::Vector3d(0.004, 0.12, 0.04);  // thin along the palm's x
  plate.pose = heldPose(held, q);
  scene.obstacles.push_back(plate);
  return scene;
}

TEST(HeldBody, IsALinkFixedToThePalmThatTheHandDoesNotCollideWith) {
  const auto held = holdingCube(0.25);
  const RobotModel& robot = held->robot;
  const int link = robot.heldLink();
  ASSERT_EQ(link, static_cast<int>(test::kr5Sdh().links().size()));
  EXPECT_EQ(robot.links()[static_cast<std::size_t>(link)].name, "cube");
  EXPECT_FALSE(robot.isHandLink(link));
  EXPECT_EQ(robot.numDofs(), test::kr5Sdh().numDofs());
  for (std::size_t l = 0; l < test::kr5Sdh().links().size(); ++l) {
    const int other = static_cast<int>(l);
    EXPECT_EQ(robot.isCollisionDisabled(other, link), robot.isHandLink(other))
        << robot.links()[l].name;
  }
  // It moves with the palm: no joint between them.
  EXPECT_EQ(robot.movingJointsBetween(link, robot.palmLink()), 0);
  const LinkPoses poses = forwardKinematics(robot, home());
  const Eigen::Vector3d expected =
      poses[static_cast<std::size_t>(robot.palmLink())] * Eigen::Vector3d(0, 0, 0.25);
  EXPECT_LT((poses[static_cast<std::size_t>(link)].translation() - expected).norm(), 1e-12);
}

TEST(HeldBody, BadBodiesAreRefusedByName) {
  const RobotModel& robot = test::kr5Sdh();
  const auto cube = std::make_shared<const TriangleMesh>(test::cube(0.05));
  test::expectErrorMentioning<InvalidArgument>(
      [&] { robot.withHeldBody(robot.links()[1].name, Eigen::Isometry3d::Identity(), cube); },
      {"held_body", "already has a link"});
  test::expectErrorMentioning<InvalidArgument>(
      [&] {
        robot.withHeldBody("cube", Eigen::Isometry3d::Identity(),
                           std::make_shared<const TriangleMesh>());
      },
      {"held_body", "no triangles"});
  Eigen::Isometry3d nan = Eigen::Isometry3d::Identity();
  nan.translation().x() = std::nan("");
  test::expectErrorMentioning<InvalidArgument>([&] { robot.withHeldBody("cube", nan, cube); },
                                               {"held_body", "finite"});
}

TEST(HeldBody, AFixedHandKeepsItsPostureAndTheArmItsLimits) {
  const RobotModel& robot = test::kr5Sdh();
  const int hand = robot.numHandDofs(), arm = robot.numArmDofs();
  const Eigen::VectorXd posture = robot.handOpen();
  const RobotModel fixed = robot.withHandFixed(posture);
  EXPECT_EQ(fixed.lowerLimits().tail(hand), posture);
  EXPECT_EQ(fixed.upperLimits().tail(hand), posture);
  EXPECT_EQ(fixed.lowerLimits().head(arm), robot.lowerLimits().head(arm));
  EXPECT_EQ(fixed.upperLimits().head(arm), robot.upperLimits().head(arm));
  EXPECT_EQ(fixed.home().tail(hand), posture);
  EXPECT_TRUE(fixed.withinLimits(fixed.home()));
  test::expectErrorMentioning<InvalidArgument>(
      [&] { robot.withHandFixed(Eigen::VectorXd::Zero(2)); }, {"hand", "finite values expected"});
  Eigen::VectorXd beyond = posture;
  beyond(0) = 100.0;
  test::expectErrorMentioning<InvalidArgument>([&] { robot.withHandFixed(beyond); },
                                               {"hand", "outside its limits"});
}

TEST(HeldBody, ItsSpheresHoldItsSurface) {
  const auto held = holdingCube(0.25, 0.1);
  const LinkSpheres& spheres = held->spheres.links.back();
  ASSERT_GE(spheres.root, 0);
  EXPECT_LE(spheres.excess, SphereModelOptions{}.tolerance + 1e-12);
  // Points on the cube's faces (its own frame = the link's).
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  for (int i = 0; i < 3000; ++i) {
    Eigen::Vector3d p(u(rng), u(rng), u(rng));
    p(i % 3) = (i / 3) % 2 == 0 ? -0.05 : 0.05;
    bool covered = false;
    for (const LinkSphere& s : spheres.spheres)
      covered = covered || (p - s.center).norm() <= s.radius + 1e-12;
    ASSERT_TRUE(covered) << p.transpose();
  }
  // The motion bound reaches the body: its corner is 0.25 + 0.087 m from the palm.
  const MotionBound bound(held->robot);
  Eigen::VectorXd step = Eigen::VectorXd::Zero(held->robot.numDofs());
  step(5) = 1.0;  // the last wrist joint turns the palm
  EXPECT_GT(bound.link(held->robot.heldLink(), step), 0.25);
}

TEST(HeldBody, CollidesWithAnObstacleTheRobotAloneMissesInBothTiers) {
  const auto held = holdingCube(0.25);
  const Scene scene = plateThroughHeld(*held, home());
  CollisionChecker without(base(), scene, nullptr);
  CollisionChecker with(*held, scene, nullptr);
  ASSERT_FALSE(without.inCollision(home()));  // the plate is clear of the robot
  for (const bool tier : {true, false}) {
    with.setSphereTier(tier);
    CollisionPair pair;
    EXPECT_TRUE(with.inCollision(home(), &pair)) << "sphere tier " << tier;
    EXPECT_EQ(pair.first, "cube");
    EXPECT_EQ(pair.second, "obstacle 'plate'");
  }
  EXPECT_GT(with.clearance(home()), -1.0);
  EXPECT_EQ(with.clearance(home()), 0.0);
}

TEST(HeldBody, ASegmentThatSwingsItThroughAnObstacleIsRefused) {
  const auto held = holdingCube(0.25);
  // The plate where the cube is halfway along a turn of the first joint:
  // both ends are free, the swing between them is not.
  Eigen::VectorXd a = home(), b = home(), middle = home();
  a(0) -= 0.4;
  b(0) += 0.4;
  const Scene scene = plateThroughHeld(*held, middle);
  CollisionChecker without(base(), scene, nullptr);
  CollisionChecker with(*held, scene, nullptr);
  ASSERT_FALSE(with.inCollision(a));
  ASSERT_FALSE(with.inCollision(b));
  EXPECT_TRUE(without.isMotionValid(a, b, 0.01));
  EXPECT_FALSE(with.isMotionValid(a, b, 0.01));
  const std::vector<Eigen::VectorXd> line{a, b};
  EXPECT_EQ(with.validSegments(line, 0.01), 0u);
}

TEST(HeldBody, HitsTheArmButNotTheHandThatHoldsIt) {
  // A cube around the fingers (0.1 m ahead of the palm, 0.16 m wide) is
  // what the hand holds: no collision with the hand's links.
  const auto aroundFingers = holdingCube(0.1, 0.16);
  const Scene empty;
  CollisionChecker holding(*aroundFingers, empty, nullptr);
  EXPECT_FALSE(holding.inCollision(home()));
  // The same cube as an obstacle: the hand is in it.
  Scene cubeObstacle;
  Obstacle cube;
  cube.name = "cube";
  cube.type = Obstacle::Type::kBox;
  cube.size = Eigen::Vector3d::Constant(0.16);
  cube.pose = heldPose(*aroundFingers, home());
  cubeObstacle.obstacles.push_back(cube);
  CollisionPair hand;
  ASSERT_TRUE(CollisionChecker(base(), cubeObstacle, nullptr).inCollision(home(), &hand));
  EXPECT_TRUE(test::kr5Sdh().isHandLink(test::kr5Sdh().linkIndex(hand.first))) << hand.first;
  // One reaching back past the wrist, its faces through the forearm,
  // collides with it (a mesh collides by its surface, as FCL checks it).
  const auto intoArm = holdingCube(-0.35, 0.4);
  CollisionChecker back(*intoArm, empty, nullptr);
  for (const bool tier : {true, false}) {
    back.setSphereTier(tier);
    CollisionPair pair;
    EXPECT_TRUE(back.inCollision(home(), &pair)) << "sphere tier " << tier;
    EXPECT_TRUE(pair.first == "cube" || pair.second == "cube")
        << pair.first << " / " << pair.second;
  }
}

TEST(HeldBody, TheTiersAgreeOnRandomConfigurations) {
  const auto held = holdingCube(0.2, 0.12);
  Scene scene;
  for (int i = 0; i < 6; ++i) {
    Obstacle box;
    box.name = "box" + std::to_string(i);
    box.type = Obstacle::Type::kBox;
    box.size = Eigen::Vector3d(0.1, 0.3, 0.1);
    box.pose.translation() = Eigen::Vector3d(0.5 * std::cos(i), 0.5 * std::sin(i), 0.2 + 0.1 * i);
    scene.obstacles.push_back(box);
  }
  CollisionChecker tier(*held, scene, nullptr);
  CollisionChecker fclOnly(*held, scene, nullptr);
  fclOnly.setSphereTier(false);
  const RobotModel& robot = held->robot;
  std::mt19937_64 rng(3);
  int colliding = 0;
  for (int i = 0; i < 2000; ++i) {
    Eigen::VectorXd q(robot.numDofs());
    for (int d = 0; d < robot.numDofs(); ++d)
      q(d) = std::uniform_real_distribution<double>(robot.lowerLimits()(d),
                                                    robot.upperLimits()(d))(rng);
    q.tail(robot.numHandDofs()) = robot.handOpen();
    const bool a = tier.inCollision(q), b = fclOnly.inCollision(q);
    ASSERT_EQ(a, b) << "configuration " << i;
    colliding += a;
  }
  EXPECT_GT(colliding, 100);
  EXPECT_LT(colliding, 1900);
}

}  // namespace
}  // namespace hfts::robot
