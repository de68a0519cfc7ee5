#include "planner/grasp_trajectory.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/invalid_argument.h"
#include "planner/grasp_motion_planner.h"

#include "plan_checks.h"

namespace hfts::planner {
namespace {

using Path = std::vector<Eigen::VectorXd>;

double distanceToPolyline(const Path& w, const Eigen::VectorXd& p) {
  double best = INFINITY;
  for (std::size_t i = 0; i + 1 < w.size(); ++i) {
    const Eigen::VectorXd d = w[i + 1] - w[i];
    const double n = d.squaredNorm();
    const double t = n > 0 ? std::clamp((p - w[i]).dot(d) / n, 0.0, 1.0) : 0.0;
    best = std::min(best, (w[i] + t * d - p).norm());
  }
  return best;
}

class TrajectoriesOfPlans : public ::testing::TestWithParam<test::SceneObject> {};

TEST_P(TrajectoriesOfPlans, AreWithinTheLimitsOnThePathAtRestAtTheEndsAndFree) {
  const PlanningWorld& world = test::bundledWorld();
  PlanRequest request =
      test::bundledSceneRequest(GetParam().scene, GetParam().object, 1, PlanAlgorithm::kCoupled);
  request.trajectory_rate = 200.0;
  request.parameters["physics_check"] = "0";  // the trajectory, not whether the grasp holds
  const PlanResult result = planGrasp(world, request);
  ASSERT_TRUE(result.success) << result.message;
  const GraspTrajectory& t = result.trajectory;
  ASSERT_GE(t.points.size(), 3u);
  const robot::RobotModel& robot = world.robot();

  // At rest on the path's ends; the hand closes from the pre-grasp, then
  // the palm lifts the object along the lift, at rest at its end.
  const Eigen::VectorXd& pregrasp = result.path[result.path.size() - 2];
  ASSERT_TRUE(result.lift.has_value());
  const Path& lift = result.lift->path;
  EXPECT_LT((t.points.front().positions - result.path.front()).norm(), 1e-12);
  EXPECT_LT((t.points.back().positions - lift.back()).norm(), 1e-9);
  EXPECT_EQ(t.points.front().velocities.norm(), 0.0);
  EXPECT_EQ(t.points.back().velocities.norm(), 0.0);
  EXPECT_DOUBLE_EQ(t.points.back().time, t.duration);
  EXPECT_GT(t.closing_start, 0.0);
  EXPECT_LT(t.closing_start, t.lift_start);
  EXPECT_LT(t.lift_start, t.duration);
  EXPECT_LE(t.deviation, TrajectoryOptions{}.max_deviation + 1e-12);

  const Path approach(result.path.begin(), result.path.end() - 1);
  const Path closing{pregrasp, result.path.back()};
  const robot::Scene scene = test::plannedScene(world, request);
  const db::ObjectDatabase& object = *world.object(request.object);
  robot::CollisionChecker checker(world.collisionModel(), scene, &object.geometry);
  const Hold hold = holdObject(world.collisionModel(), scene.robot_base, object.geometry,
                               object.name, scene.target_pose, result.path.back());
  robot::Scene obstacles = scene;
  obstacles.target_object.clear();
  robot::CollisionChecker held(*hold.model, obstacles, nullptr);
  for (std::size_t i = 0; i < t.points.size(); ++i) {
    const TrajectoryPoint& p = t.points[i];
    SCOPED_TRACE("sample at " + std::to_string(p.time) + " s");
    if (i > 0) {
      EXPECT_GT(p.time, t.points[i - 1].time);
      EXPECT_LE(p.time - t.points[i - 1].time, 1.0 / 200.0 + 1e-12);
    }
    ASSERT_LE((p.velocities.cwiseAbs() - robot.maxVelocities()).maxCoeff(), 1e-6);
    ASSERT_LE((p.accelerations.cwiseAbs() - robot.maxAccelerations()).maxCoeff(), 1e-6);
    EXPECT_TRUE(robot.withinLimits(p.positions, 1e-9));
    const bool liftPhase = p.time > t.lift_start;
    const bool closingPhase = !liftPhase && p.time > t.closing_start;
    ASSERT_LE(distanceToPolyline(liftPhase      ? lift
                                 : closingPhase ? closing
                                                : approach,
                                 p.positions),
              t.deviation + 1e-9);
    if (liftPhase) {  // the object in the hand, the hand closed
      ASSERT_FALSE(held.inCollision(p.positions));
      EXPECT_LT((p.positions - lift.front()).tail(robot.numHandDofs()).norm(), 1e-9);
    } else {
      ASSERT_FALSE(closingPhase ? checker.inCollision(p.positions, robot::CollisionRequest::grasp())
                                : checker.inCollision(p.positions));
    }
    if (closingPhase) {  // the arm stands still while the hand closes
      EXPECT_LT((p.positions - pregrasp).head(robot.numArmDofs()).norm(), 1e-9);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, TrajectoriesOfPlans,
                         ::testing::Values(test::SceneObject{"table", "mug"},
                                           test::SceneObject{"shelf", "bottle"},
                                           test::SceneObject{"bin", "blob"}),
                         test::sceneObjectName);

TEST(GraspTrajectory, RateZeroGivesNoTrajectoryAndBadRatesAreRefused) {
  const PlanningWorld& world = test::bundledWorld();
  PlanRequest request = test::bundledSceneRequest("table", "mug", 1, PlanAlgorithm::kCoupled);
  request.parameters["physics_check"] = "0";
  request.trajectory_rate = 0.0;
  const PlanResult result = planGrasp(world, request);
  ASSERT_TRUE(result.success);
  EXPECT_TRUE(result.trajectory.points.empty());
  for (double bad : {-1.0, 1001.0, std::nan("")}) {
    request.trajectory_rate = bad;
    try {
      planGrasp(world, request);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InvalidArgument& e) {
      EXPECT_EQ(e.field(), "trajectory_rate");
    }
  }
  robot::CollisionChecker checker(world.collisionModel(), robot::Scene{}, nullptr);
  EXPECT_THROW(graspTrajectory({world.robot().home()}, checker, MotionCheck{0.0025}, 100),
               InvalidArgument);
}

TEST(GraspTrajectory, AMotionAtAFractionOfTheSpeedIsTheSameMotionSlowerBy1OverIt) {
  // Half the velocity limits and a quarter of the acceleration limits: the
  // same time law stretched twice, within half the velocity limits.
  const robot::RobotModel& robot = test::kr5Sdh();
  Eigen::VectorXd a = robot.home(), b = a, c = a;
  b[0] += 0.8;
  c[0] += 0.8;
  c[2] -= 0.4;
  robot::CollisionChecker free(test::collisionOf(robot), robot::Scene{}, nullptr);
  const GraspTrajectory full = motionTrajectory({a, b, c}, free, MotionCheck{0.0025}, 100);
  const GraspTrajectory half = motionTrajectory({a, b, c}, free, MotionCheck{0.0025}, 100, nullptr,
                                                TrajectoryOptions{}.max_deviation, 0.5);
  ASSERT_FALSE(full.points.empty() || half.points.empty());
  EXPECT_NEAR(half.duration / full.duration, 2.0, 1e-6);
  for (const TrajectoryPoint& p : half.points) {
    EXPECT_TRUE(
        (p.velocities.cwiseAbs().array() <= 0.5 * robot.maxVelocities().array() * (1 + 1e-6)).all())
        << "at " << p.time;
    // Where the slow one is at t, the fast one was at t / 2.
    double nearest = INFINITY;
    for (const TrajectoryPoint& q : full.points)
      if (std::abs(q.time - p.time / 2.0) < 0.006)
        nearest = std::min(nearest, (q.positions - p.positions).norm());
    EXPECT_LT(nearest, 0.05) << "at " << p.time;
  }
  for (double bad : {0.0, -0.5, 1.5, std::nan("")})
    EXPECT_THROW(motionTrajectory({a, b, c}, free, MotionCheck{0.0025}, 100, nullptr,
                                  TrajectoryOptions{}.max_deviation, bad),
                 InvalidArgument);
}

TEST(GraspTrajectory, ABlendThatWouldCollideIsTightened) {
  // A corner around a box placed where the blend cuts it: the blend's chord
  // enters the box, so the trajectory keeps to the planned path instead.
  const robot::RobotModel& robot = test::kr5Sdh();
  const Eigen::VectorXd home = robot.home();
  Eigen::VectorXd a = home, b = home, c = home;
  b[0] += 1.2;
  c[0] += 1.2;
  c[1] += 0.8;
  robot::Scene open;
  robot::CollisionChecker free(test::collisionOf(robot), open, nullptr);
  const GraspTrajectory wide =
      graspTrajectory({a, b, c, c}, free, MotionCheck{0.0025}, 100, nullptr, 0.5);
  ASSERT_FALSE(wide.points.empty());
  EXPECT_GT(wide.deviation, 0.15);
  // Where the blend's midpoint puts the palm, an obstacle: blends must
  // shrink until they keep out of it.
  const TimeOptimalTrajectory probe({a, b, c}, robot.maxVelocities(), robot.maxAccelerations(),
                                    {0.5, 1e-3});
  Eigen::VectorXd mid = probe.at(0.5 * probe.duration()).positions;
  double farthest = 0.0;
  for (double s = 0; s <= probe.duration(); s += 0.01) {
    const Eigen::VectorXd q = probe.at(s).positions;
    if (distanceToPolyline({a, b, c}, q) > farthest) {
      farthest = distanceToPolyline({a, b, c}, q);
      mid = q;
    }
  }
  // A small ball where some link is at the blend's farthest point but no
  // link passes on the planned path.
  const robot::LinkPoses poses = robot::forwardKinematics(robot, mid);
  robot::Scene blocked;
  for (const Eigen::Isometry3d& link : poses) {
    robot::Obstacle ball;
    ball.name = "in_the_blend";
    ball.type = robot::Obstacle::Type::kSphere;
    ball.pose = Eigen::Isometry3d(Eigen::Translation3d(link.translation()));
    ball.size = Eigen::Vector3d(0.01, 0, 0);
    robot::Scene candidate;
    candidate.obstacles.push_back(ball);
    robot::CollisionChecker check(test::collisionOf(robot), candidate, nullptr);
    if (check.inCollision(mid) && check.isMotionValid(a, b, 0.0025) &&
        check.isMotionValid(b, c, 0.0025)) {
      blocked = candidate;
      break;
    }
  }
  ASSERT_EQ(blocked.obstacles.size(), 1u) << "no link is off the path at the blend";
  robot::CollisionChecker checker(test::collisionOf(robot), blocked, nullptr);
  const GraspTrajectory tight =
      graspTrajectory({a, b, c, c}, checker, MotionCheck{0.0025}, 100, nullptr, 0.5);
  ASSERT_FALSE(tight.points.empty());
  EXPECT_LT(tight.deviation, wide.deviation);
  for (const TrajectoryPoint& p : tight.points) EXPECT_FALSE(checker.inCollision(p.positions));
}

}  // namespace
}  // namespace hfts::planner
