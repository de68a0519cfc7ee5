#include "planner/path_smoothing.h"

#include <gtest/gtest.h>

#include "robot/kinematics.h"
#include "robot/scene.h"
#include "robot_fixture.h"
#include "test_meshes.h"

namespace hfts::planner {
namespace {

namespace ob = ompl::base;

/// The robot alone (no obstacles, no target) or in the table scene.
struct Fixture {
  explicit Fixture(const robot::Scene& scene, double treeResolution = 0.02)
      : checker(test::collisionOf(test::kr5Sdh()), scene, nullptr),
        si(makeSpaceInformation(test::kr5Sdh(), checker, treeResolution)) {}
  const WeightedStateSpace& space() const { return *si->getStateSpace()->as<WeightedStateSpace>(); }
  const CollisionMotionValidator& validator() const {
    return dynamic_cast<const CollisionMotionValidator&>(*si->getMotionValidator());
  }
  robot::CollisionChecker checker;
  ob::SpaceInformationPtr si;
};

robot::Scene emptyScene() {
  robot::Scene scene;
  scene.name = "empty";
  return scene;
}

robot::Scene tableScene() {
  return robot::loadScene(test::sourcePath("objects/scenes/table.json"));
}

/// A zig-zag of free configurations around the home pose: shortcutting
/// can only shorten it.
std::vector<Eigen::VectorXd> zigZag() {
  const Eigen::VectorXd home = test::kr5Sdh().home();
  const Eigen::Index n = home.size();
  std::vector<Eigen::VectorXd> path{home};
  for (int i = 1; i <= 6; ++i)
    path.push_back(home + 0.15 * i * Eigen::VectorXd::Unit(n, 0) +
                   (i % 2 == 0 ? 0.3 : -0.3) * Eigen::VectorXd::Unit(n, 3));
  return path;
}

/// The table scene's start, then the shoulder forward and down through
/// the table top (as in the planner's start-in-collision test).
std::vector<Eigen::VectorXd> throughTheTable() {
  const robot::Scene scene = tableScene();
  return {*scene.startFor("kr5_sdh"),
          (Eigen::VectorXd(13) << 0, 0.6, 0.5, 0, 1.57, 0, 0, -0.2, 0.2, -0.2, 0.2, -0.2, 0.2)
              .finished()};
}

/// A ball where the palm is at the home pose: swinging the first joint
/// through home hits it, swinging with the elbow raised passes above it.
robot::Scene ballAtThePalm() {
  const robot::RobotModel& robot = test::kr5Sdh();
  robot::Obstacle ball;
  ball.name = "ball";
  ball.type = robot::Obstacle::Type::kSphere;
  ball.size = Eigen::Vector3d(0.03, 0, 0);
  ball.pose.translation() =
      robot::forwardKinematics(robot, robot.home())[static_cast<std::size_t>(robot.palmLink())]
          .translation();
  robot::Scene scene = emptyScene();
  scene.obstacles.push_back(ball);
  return scene;
}

/// From the first joint at -0.6 to +0.6 rad around the ball, over it, in
/// short straight pieces.
std::vector<Eigen::VectorXd> overTheBall() {
  const Eigen::VectorXd home = test::kr5Sdh().home();
  const Eigen::Index n = home.size();
  const Eigen::VectorXd swing = Eigen::VectorXd::Unit(n, 0);
  const Eigen::VectorXd raise = -0.5 * Eigen::VectorXd::Unit(n, 1);
  const Eigen::VectorXd a = home - 0.6 * swing, b = a + raise, c = b + 1.2 * swing, d = c - raise;
  std::vector<Eigen::VectorXd> path;
  for (const auto& [from, to] : {std::pair{a, b}, {b, c}, {c, d}})
    for (int i = 0; i < 4; ++i) path.push_back(from + (to - from) * (i / 4.0));
  path.push_back(d);
  return path;
}

const ob::PlannerTerminationCondition kNever = ob::plannerNonTerminatingCondition();

TEST(PathSmoothing, ShortensAndKeepsTheEndPoints) {
  const Fixture f(emptyScene());
  const std::vector<Eigen::VectorXd> raw = zigZag();
  ASSERT_TRUE(denselyValid(f.validator(), raw, 0.0025));
  const std::vector<Eigen::VectorXd> smoothed = smoothPath(f.si, raw, {}, kNever);
  ASSERT_GE(smoothed.size(), 2u);
  EXPECT_EQ(smoothed.front(), raw.front());
  EXPECT_EQ(smoothed.back(), raw.back());
  EXPECT_LT(pathLength(f.space(), smoothed), pathLength(f.space(), raw));
}

TEST(PathSmoothing, OnlyCornersOfTheFoundPathSurvive) {
  // overTheBall's four points per straight piece: the points inside a
  // piece are dropped, the corners b and c only where no straight motion
  // replaces them (the direct swing hits the ball).
  const Fixture f(ballAtThePalm());
  const std::vector<Eigen::VectorXd> raw = overTheBall();
  ASSERT_FALSE(denselyValid(f.validator(), {raw.front(), raw.back()}, 0.02));
  const std::vector<Eigen::VectorXd> smoothed = smoothPath(f.si, raw, {}, kNever);
  EXPECT_EQ(smoothed.front(), raw.front());
  EXPECT_EQ(smoothed.back(), raw.back());
  EXPECT_TRUE(denselyValid(f.validator(), smoothed, 0.02));
  EXPECT_LT(pathLength(f.space(), smoothed), pathLength(f.space(), raw));
  for (std::size_t i = 1; i + 1 < smoothed.size(); ++i)
    for (std::size_t k = 1; k + 1 < raw.size(); ++k) {
      if (smoothed[i] != raw[k]) continue;
      EXPECT_EQ(k % 4, 0u) << "vertex " << i << " is raw point " << k
                           << ", inside a straight piece";
    }
}

TEST(PathSmoothing, TheSeedFixesTheResult) {
  const Fixture f(emptyScene());
  PathSmoothing a;
  a.seed = 7;
  const auto first = smoothPath(f.si, zigZag(), a, kNever);
  const auto second = smoothPath(f.si, zigZag(), a, kNever);
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t i = 0; i < first.size(); ++i) EXPECT_EQ(first[i], second[i]);
}

TEST(PathSmoothing, ZeroStepsOrTwoStatesLeaveThePathAlone) {
  const Fixture f(emptyScene());
  PathSmoothing none;
  none.steps = 0;
  EXPECT_EQ(smoothPath(f.si, zigZag(), none, kNever), zigZag());
  const std::vector<Eigen::VectorXd> segment{zigZag().front(), zigZag().back()};
  EXPECT_EQ(smoothPath(f.si, segment, {}, kNever), segment);
}

TEST(PathSmoothing, DenseCheckFindsACollidingSegment) {
  const Fixture f(tableScene());
  EXPECT_FALSE(denselyValid(f.validator(), throughTheTable(), 0.0025));
  EXPECT_FALSE(denselyValid(f.validator(), {}, 0.0025));
  EXPECT_TRUE(denselyValid(f.validator(), {throughTheTable().front()}, 0.0025));
}

TEST(PathSmoothing, SmoothAndRecheckReturnsOnlyCheckedPaths) {
  const Fixture free(emptyScene());
  const auto kept = smoothAndRecheck(free.si, zigZag(), {}, kNever);
  ASSERT_TRUE(kept.has_value());
  EXPECT_TRUE(denselyValid(free.validator(), *kept, 0.0025));
  const Fixture table(tableScene());
  EXPECT_FALSE(smoothAndRecheck(table.si, throughTheTable(), {}, kNever).has_value());
}

TEST(PathSmoothing, AShortcutThatGrazesBetweenTreeSamplesIsRepaired) {
  // Trees checked every 0.5: the straight swing through the ball passes the
  // tree check but not the dense re-check.
  const Fixture f(ballAtThePalm(), 0.5);
  const std::vector<Eigen::VectorXd> raw = overTheBall();
  ASSERT_TRUE(denselyValid(f.validator(), raw, 0.0025));
  ASSERT_FALSE(denselyValid(f.validator(), {raw.front(), raw.back()}, 0.0025));
  ASSERT_TRUE(denselyValid(f.validator(), {raw.front(), raw.back()}, 0.5));
  ASSERT_FALSE(denselyValid(f.validator(), smoothPath(f.si, raw, {}, kNever), 0.0025))
      << "the smoother no longer takes the grazing shortcut: the test checks nothing";
  const auto kept = smoothAndRecheck(f.si, raw, {}, kNever);
  ASSERT_TRUE(kept.has_value());
  EXPECT_TRUE(denselyValid(f.validator(), *kept, 0.0025));
  EXPECT_EQ(kept->front(), raw.front());
  EXPECT_EQ(kept->back(), raw.back());
  // Smoothed, not the unsmoothed path.
  EXPECT_LT(pathLength(f.space(), *kept), pathLength(f.space(), raw) - 1e-6);
  EXPECT_EQ(f.validator().resolution(), 0.5) << "the tree resolution is restored";
}

TEST(PathSmoothing, LengthIsTheSumOfWeightedSegments) {
  const Fixture f(emptyScene());
  const std::vector<Eigen::VectorXd> path = zigZag();
  double sum = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) sum += f.space().distance(path[i - 1], path[i]);
  EXPECT_DOUBLE_EQ(pathLength(f.space(), path), sum);
  EXPECT_EQ(pathLength(f.space(), {path.front()}), 0.0);
}

}  // namespace
}  // namespace hfts::planner
