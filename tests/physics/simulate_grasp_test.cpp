#include "physics/simulate_grasp.h"

#include <gtest/gtest.h>

#include <sstream>
#include <thread>

#include "core/invalid_argument.h"
#include "panda_cube.h"
#include "physics/lift_path.h"
#include "test_meshes.h"

namespace hfts::physics {
namespace {

/// The verdict in full, for failure messages.
std::string describe(const GraspVerdict& v) {
  std::ostringstream out;
  out << "held " << v.held << " (" << v.held_fraction << "), mass " << v.mass << " kg, lift "
      << v.lift_direction << "\n";
  for (const TrialResult& t : v.trials)
    out << "  " << t.name << ": held " << t.held << ", moved " << t.max_displacement * 1000
        << " mm, turned " << t.max_rotation * 180 / M_PI << " deg, " << t.fingers_in_contact
        << " fingers; " << t.failure << "\n";
  return out.str();
}

GraspVerdict simulate(const robot::RobotModel& robot, const test::PandaCube& world,
                      const Eigen::VectorXd& pregrasp, const Eigen::VectorXd& grasp,
                      const SimulationOptions& options = {}) {
  // The bundled Panda's collision model is built once; a changed Panda's here.
  std::shared_ptr<const robot::CollisionModel> own;
  if (&robot != &test::panda()) own = robot::buildCollisionModel(robot);
  return simulateGrasp(own ? *own : test::collisionOf(robot), world.scene, test::smallCube(),
                       pregrasp, grasp, options);
}

/// The Panda with `from` replaced by `to` in its robot config.
robot::RobotModel pandaWith(const std::string& from, const std::string& to) {
  const std::string urdf =
      test::readBytes(test::sourcePath("robots/panda_gripper/panda_gripper.urdf"));
  std::string config = test::readBytes(test::sourcePath("robots/panda_gripper/panda_gripper.json"));
  config.replace(config.find(from), from.size(), to);
  return robot::RobotModel::fromStrings(urdf, config, "changed panda");
}

/// The Panda with its grasping force scaled (the config's efforts times `scale`).
robot::RobotModel pandaWithEffortScaled(double scale) {
  return pandaWith("\"efforts\": [70]", "\"efforts\": [" + std::to_string(70 * scale) + "]");
}

/// The nominal trial alone with short disturbances: quick.
GraspVerdict quickNominal(const test::PandaCube& world) {
  SimulationOptions options;
  options.perturb = false;
  options.disturbance_time = 0.2;
  return simulate(test::panda(), world, world.pregrasp, world.grasp, options);
}

TEST(SimulateGrasp, PandaSqueezingTheCubeHoldsItThroughLiftHoldAndAllSixDisturbances) {
  const test::PandaCube world;
  const GraspVerdict v = simulate(test::panda(), world, world.pregrasp, world.grasp);
  EXPECT_TRUE(v.held) << describe(v);
  EXPECT_EQ(v.held_fraction, 1.0) << describe(v);
  ASSERT_EQ(v.trials.size(), 7u);
  EXPECT_EQ(v.trials[0].name, "nominal");
  for (const TrialResult& t : v.trials) {
    EXPECT_TRUE(t.failure.empty()) << t.name << ": " << t.failure;
    EXPECT_LT(t.max_displacement, 0.002) << t.name;  // far inside the 20 mm tolerance
    EXPECT_LT(t.max_rotation, 0.02) << t.name;
    EXPECT_EQ(t.fingers_in_contact, 2) << t.name;
    // The whole protocol: settle 0.3 + close 1 + lift 1 + hold 2 + 6 x 1 s.
    EXPECT_NEAR(t.simulated_time, 10.3, 1e-6) << t.name;
  }
  EXPECT_EQ(v.lift_direction, "up");
  EXPECT_EQ(v.collision_shape, "convex_parts");
  EXPECT_NEAR(v.shape_fidelity, 1.0, 1e-9);  // a cube is one piece, its hull
  EXPECT_NEAR(v.mass, 1000 * 0.046 * 0.046 * 0.046, 1e-4);
}

TEST(SimulateGrasp, AStopEndsTheTrialItIsInWithinAPollAndRunsNoOther) {
  // The stop says "now" on its fifth poll: three before the first trial
  // (before and after planning the lift, before the trial), then every
  // kStopPollSteps time steps within it, far before its end.
  const test::PandaCube world;
  SimulationOptions options;
  int polls = 0;
  options.stop = [&polls] { return ++polls >= 5; };
  const GraspVerdict v = simulate(test::panda(), world, world.pregrasp, world.grasp, options);
  EXPECT_EQ(polls, 5);
  EXPECT_TRUE(v.stopped);
  EXPECT_FALSE(v.held);
  ASSERT_EQ(v.trials.size(), 1u) << describe(v);
  EXPECT_TRUE(v.trials[0].stopped);
  EXPECT_EQ(v.trials[0].failure, "stopped");
  // It ended 2 x 64 steps of 2 ms in, in the settle.
  ASSERT_FALSE(v.nominal_motion.empty());
  EXPECT_LE(v.nominal_motion.back().time,
            2.0 * kStopPollSteps * SimulationOptions{}.timestep + 0.05);
}

TEST(SimulateGrasp, TheNominalMotionFollowsTheLift) {
  const test::PandaCube world;
  SimulationOptions options;
  options.perturb = false;
  const GraspVerdict v = simulate(test::panda(), world, world.pregrasp, world.grasp, options);
  ASSERT_FALSE(v.nominal_motion.empty());
  const MotionSample& first = v.nominal_motion.front();
  const MotionSample& last = v.nominal_motion.back();
  EXPECT_EQ(first.phase, "settle");
  EXPECT_EQ(first.configuration.size(), test::panda().numDofs());
  // 50 Hz over 0.3 + 1 + 1 + 2 + 6 x 1 s.
  EXPECT_NEAR(static_cast<double>(v.nominal_motion.size()), 50 * 10.3, 2);
  const auto rising = [&](const std::string& phase) {
    for (const MotionSample& s : v.nominal_motion)
      if (s.phase == phase) return s.object.translation().z();
    return 0.0;
  };
  EXPECT_NEAR(rising("hold") - first.object.translation().z(), 0.10, 0.005);
  EXPECT_EQ(last.phase, "disturbance -z");
}

TEST(SimulateGrasp, TheTrialsFollowTheLiftTheyAreGivenAtTheProtocolsSpeed) {
  // A plan's lift (e.g. out from under a board): 10 cm up, then 20 cm
  // along y. Followed instead of the protocol's own, over 1 s per 10 cm of
  // palm travel: 3 s.
  const test::PandaCube world;
  const robot::RobotModel& panda = test::panda();
  const PalmLine up =
      straightPalmLine(panda, world.scene.robot_base, world.grasp, Eigen::Vector3d::UnitZ(), 0.1);
  const PalmLine aside = straightPalmLine(panda, world.scene.robot_base, up.waypoints.back(),
                                          Eigen::Vector3d::UnitY(), 0.2);
  ASSERT_TRUE(up.problem.empty() && aside.problem.empty()) << up.problem << aside.problem;
  std::vector<Eigen::VectorXd> lift = up.waypoints;
  lift.insert(lift.end(), aside.waypoints.begin() + 1, aside.waypoints.end());
  SimulationOptions options;
  options.perturb = false;
  const GraspVerdict v = simulateGrasp(test::collisionOf(panda), world.scene, test::smallCube(),
                                       world.pregrasp, world.grasp, options, &lift);
  EXPECT_TRUE(v.held) << describe(v);
  EXPECT_EQ(v.lift_direction, "plan");
  ASSERT_EQ(v.trials.size(), 1u);
  EXPECT_NEAR(v.trials[0].simulated_time, 10.3 + 2.0, 1e-6);
  const MotionSample& first = v.nominal_motion.front();
  for (const MotionSample& s : v.nominal_motion)
    if (s.phase == "hold") {
      const Eigen::Vector3d moved = s.object.translation() - first.object.translation();
      EXPECT_NEAR(moved.z(), 0.1, 0.005);
      EXPECT_NEAR(moved.y(), 0.2, 0.005);
      break;
    }

  // A lift that does not start at the grasp, or of partial configurations.
  std::vector<Eigen::VectorXd> elsewhere(lift.begin() + 5, lift.end());
  std::vector<Eigen::VectorXd> partial{world.grasp.head(7)};
  for (const auto* bad : {&elsewhere, &partial}) {
    try {
      simulateGrasp(test::collisionOf(panda), world.scene, test::smallCube(), world.pregrasp,
                    world.grasp, options, bad);
      ADD_FAILURE() << "no error";
    } catch (const InvalidArgument& e) {
      EXPECT_EQ(e.field(), "lift") << e.what();
    }
  }
}

TEST(SimulateGrasp, TheCubeStaysOnTheTableWhenTheHandStaysOpen) {
  const test::PandaCube world;
  SimulationOptions options;
  options.perturb = false;
  const GraspVerdict v = simulate(test::panda(), world, world.pregrasp, world.pregrasp, options);
  EXPECT_FALSE(v.held) << describe(v);
  ASSERT_EQ(v.trials.size(), 1u);
  EXPECT_EQ(v.trials[0].fingers_in_contact, 0);
  EXPECT_EQ(v.trials[0].failure.rfind("lift: object slipped", 0), 0u) << v.trials[0].failure;
  EXPECT_GT(v.trials[0].max_displacement, 0.02);
  // It stopped in the lift: after settle and close, before the lift's end.
  EXPECT_GT(v.trials[0].simulated_time, 1.3);
  EXPECT_LT(v.trials[0].simulated_time, 2.3);
}

TEST(SimulateGrasp, WithoutFrictionTheSqueezedCubeSlipsOut) {
  const test::PandaCube world;
  SimulationOptions options;
  options.friction = 0.0;
  const GraspVerdict v = simulate(test::panda(), world, world.pregrasp, world.grasp, options);
  EXPECT_FALSE(v.held) << describe(v);
  EXPECT_EQ(v.held_fraction, 0.0) << describe(v);
  EXPECT_EQ(v.trials[0].failure.rfind("lift: object slipped", 0), 0u) << describe(v);
}

TEST(SimulateGrasp, AHandTooWeakToCarryTheWeightDropsTheCube) {
  // Each jaw presses with half the DoF's effort; the cube holds while
  // 2 mu (effort / 2) = mu effort >= m g, here 0.5 x 1.4 N = 0.7 N < 0.95 N.
  const double scale = 0.02;
  const robot::RobotModel weak = pandaWithEffortScaled(scale);
  const double weight = 1000 * 0.046 * 0.046 * 0.046 * 9.81;
  ASSERT_LT(0.5 * 70 * scale, weight);
  const test::PandaCube world;
  const GraspVerdict v = simulate(weak, world, world.pregrasp, world.grasp);
  EXPECT_FALSE(v.held) << describe(v);
  EXPECT_EQ(v.trials[0].failure.rfind("lift: object slipped", 0), 0u) << describe(v);
  // Twice that force carries it, though no longer against every disturbance.
  const GraspVerdict stronger =
      simulate(pandaWithEffortScaled(2 * scale), world, world.pregrasp, world.grasp);
  EXPECT_EQ(stronger.trials[0].failure.rfind("lift", 0), std::string::npos) << describe(stronger);
}

TEST(SimulateGrasp, SameInputsGiveTheSameVerdict) {
  const test::PandaCube world;
  const GraspVerdict a = quickNominal(world);
  const GraspVerdict b = quickNominal(world);
  EXPECT_EQ(a.trials[0].max_displacement, b.trials[0].max_displacement);
  EXPECT_EQ(a.trials[0].max_rotation, b.trials[0].max_rotation);
  EXPECT_TRUE(a.nominal_motion.back().object.isApprox(b.nominal_motion.back().object, 0.0));
}

TEST(SimulateGrasp, CallsOnSeveralThreadsAtOnceGiveTheSameVerdicts) {
  const test::PandaCube world;
  const GraspVerdict alone = quickNominal(world);
  std::vector<GraspVerdict> verdicts(2);
  std::vector<std::thread> threads;
  for (GraspVerdict& v : verdicts) threads.emplace_back([&] { v = quickNominal(world); });
  for (std::thread& t : threads) t.join();
  for (const GraspVerdict& v : verdicts) {
    EXPECT_EQ(v.trials[0].max_displacement, alone.trials[0].max_displacement);
    EXPECT_EQ(v.nominal_motion.size(), alone.nominal_motion.size());
  }
}

TEST(SimulateGrasp, BadInputNamesTheField) {
  const test::PandaCube world;
  const auto expectField = [&](const std::string& field, const Eigen::VectorXd& pregrasp,
                               const Eigen::VectorXd& grasp, const SimulationOptions& options) {
    try {
      simulate(test::panda(), world, pregrasp, grasp, options);
      ADD_FAILURE() << "no error for " << field;
    } catch (const InvalidArgument& e) {
      EXPECT_EQ(e.field(), field) << e.what();
    }
  };
  expectField("pregrasp", world.pregrasp.head(7), world.grasp, {});
  Eigen::VectorXd nan = world.grasp;
  nan(3) = std::nan("");
  expectField("grasp", world.pregrasp, nan, {});
  Eigen::VectorXd outside = world.grasp;
  outside(7) = 0.05;  // the jaws open 40 mm at most
  expectField("grasp", world.pregrasp, outside, {});
  SimulationOptions options;
  options.friction = -0.1;
  expectField("options.friction", world.pregrasp, world.grasp, options);
  options = {};
  options.density = std::numeric_limits<double>::infinity();
  expectField("options.density", world.pregrasp, world.grasp, options);
  options = {};
  options.timestep = 0.01;
  expectField("options.timestep", world.pregrasp, world.grasp, options);
  options = {};
  options.min_held_fraction = 1.5;
  expectField("options.min_held_fraction", world.pregrasp, world.grasp, options);
}

TEST(SimulateGrasp, ARobotWithoutHandActuationIsRefused) {
  const robot::RobotModel bare = pandaWith("\"hand_actuation\"", "\"unused_actuation\"");
  const test::PandaCube world;
  try {
    simulate(bare, world, world.pregrasp, world.grasp);
    ADD_FAILURE() << "no error";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.field(), "robot.hand_actuation");
  }
}

}  // namespace
}  // namespace hfts::physics
