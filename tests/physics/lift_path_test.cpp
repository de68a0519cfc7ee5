#include "physics/lift_path.h"

#include <gtest/gtest.h>

#include "core/invalid_argument.h"
#include "panda_cube.h"
#include "robot/kinematics.h"

namespace hfts::physics {
namespace {

Eigen::Isometry3d palmOf(const robot::RobotModel& robot, const Eigen::VectorXd& q) {
  return robot::forwardKinematics(robot, q)[static_cast<std::size_t>(robot.palmLink())];
}

TEST(LiftPath, ThePalmMovesAlongTheLineKeepingItsOrientation) {
  const test::PandaCube world;
  const robot::RobotModel& panda = test::panda();
  const Eigen::Vector3d direction(1, 0, 2);
  const PalmLine line =
      straightPalmLine(panda, world.scene.robot_base, world.grasp, direction, 0.1, 0.005);
  EXPECT_TRUE(line.problem.empty()) << line.problem;
  ASSERT_EQ(line.waypoints.size(), 21u);
  const Eigen::Isometry3d start = palmOf(panda, world.grasp);
  for (std::size_t k = 0; k < line.waypoints.size(); ++k) {
    const Eigen::Isometry3d palm = palmOf(panda, line.waypoints[k]);
    const Eigen::Vector3d expected = start.translation() + 0.005 * k * direction.normalized();
    EXPECT_LT((palm.translation() - expected).norm(), 1e-6) << k;
    EXPECT_LT(Eigen::AngleAxisd(palm.linear() * start.linear().transpose()).angle(), 1e-5) << k;
    EXPECT_EQ(line.waypoints[k](7), world.grasp(7));  // the hand stays as it was
    EXPECT_TRUE(panda.withinLimits(line.waypoints[k]));
  }
  // Small joint steps: a path, not a jump to another IK branch.
  for (std::size_t k = 1; k < line.waypoints.size(); ++k)
    EXPECT_LT((line.waypoints[k] - line.waypoints[k - 1]).cwiseAbs().maxCoeff(), 0.05);
}

TEST(LiftPath, ALineBeyondTheArmsReachStopsWhereItGotTo) {
  const test::PandaCube world;
  const PalmLine line = straightPalmLine(test::panda(), world.scene.robot_base, world.grasp,
                                         Eigen::Vector3d::UnitX(), 2.0, 0.01);
  EXPECT_NE(line.problem.find("cannot follow the line beyond"), std::string::npos);
  EXPECT_GT(line.waypoints.size(), 10u);
  EXPECT_LT(line.waypoints.size(), 100u);
}

TEST(LiftPath, TheCubeIsLiftedUpInFreeSpace) {
  const test::PandaCube world;
  const LiftPlan plan = planLift(test::collisionOf(test::panda()), world.scene, world.grasp, 0.1);
  EXPECT_EQ(plan.direction, "up");
  ASSERT_EQ(plan.line.waypoints.size(), 21u);
  const Eigen::Vector3d rise = palmOf(test::panda(), plan.line.waypoints.back()).translation() -
                               palmOf(test::panda(), world.grasp).translation();
  EXPECT_TRUE(rise.isApprox(Eigen::Vector3d(0, 0, 0.1), 1e-6));
}

robot::Obstacle box(const std::string& name, const Eigen::Vector3d& size,
                    const Eigen::Vector3d& center) {
  robot::Obstacle b;
  b.name = name;
  b.type = robot::Obstacle::Type::kBox;
  b.size = size;
  b.pose.translation() = center;
  return b;
}

TEST(LiftPath, UnderAShelfBoardThePalmRetreatsAlongItsApproachAxis) {
  // A board 6 cm above the hand: up is blocked, and so is retreating (the
  // palm points down, so its retreat is up too).
  test::PandaCube world;
  const Eigen::Vector3d top = world.center() + Eigen::Vector3d(0, 0, 0.17);
  world.scene.obstacles.push_back(box("board", Eigen::Vector3d(0.2, 0.3, 0.02), top));
  const LiftPlan blocked =
      planLift(test::collisionOf(test::panda()), world.scene, world.grasp, 0.1);
  EXPECT_EQ(blocked.direction, "up_blocked");
  EXPECT_NE(blocked.blocked_by.find("board"), std::string::npos) << blocked.blocked_by;
  EXPECT_EQ(blocked.line.waypoints.size(), 21u);  // lifted up all the same
}

TEST(LiftPath, APalmThatApproachedSidewaysRetreatsWhenABoardIsAboveIt) {
  // The palm horizontal, its approach axis along +x, 20 cm above the
  // floor, under a board: up is blocked, straight back (-x) is free.
  robot::Scene scene;
  Eigen::Isometry3d palm = Eigen::Isometry3d::Identity();
  palm.linear() << 0, 0, 1, 0, 1, 0, -1, 0, 0;
  palm.translation() = Eigen::Vector3d(0.4, 0.0, 0.2);
  std::mt19937_64 rng(1);
  const auto arms = robot::ArmIk(test::panda()).solvePalm(palm, rng);
  ASSERT_FALSE(arms.empty());
  Eigen::VectorXd q(8);
  q << arms.front(), 0.02;
  scene.obstacles.push_back(
      box("board", Eigen::Vector3d(0.3, 0.4, 0.02), Eigen::Vector3d(0.5, 0, 0.27)));
  const LiftPlan plan = planLift(test::collisionOf(test::panda()), scene, q, 0.1);
  EXPECT_EQ(plan.direction, "retreat");
  ASSERT_EQ(plan.line.waypoints.size(), 21u);
  const Eigen::Vector3d moved =
      palmOf(test::panda(), plan.line.waypoints.back()).translation() - palm.translation();
  EXPECT_TRUE(moved.isApprox(Eigen::Vector3d(-0.1, 0, 0), 1e-6)) << moved.transpose();
}

TEST(LiftPath, BadInputNamesTheField) {
  const test::PandaCube world;
  const auto fieldOf = [&](const Eigen::VectorXd& start, const Eigen::Vector3d& direction,
                           double distance, double step) {
    try {
      straightPalmLine(test::panda(), world.scene.robot_base, start, direction, distance, step);
    } catch (const InvalidArgument& e) {
      return e.field();
    }
    return std::string("no error");
  };
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  EXPECT_EQ(fieldOf(world.grasp.head(7), up, 0.1, 0.005), "start");
  EXPECT_EQ(fieldOf(world.grasp, Eigen::Vector3d::Zero(), 0.1, 0.005), "direction");
  EXPECT_EQ(fieldOf(world.grasp, up, -0.1, 0.005), "distance");
  EXPECT_EQ(fieldOf(world.grasp, up, 0.1, 0.0), "step");
}

}  // namespace
}  // namespace hfts::physics
