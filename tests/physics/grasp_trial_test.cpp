#include "grasp_trial.h"

#include <gtest/gtest.h>

#include "panda_cube.h"
#include "physics/lift_path.h"
#include "physics/mjcf_scene.h"

namespace hfts::physics {
namespace {

/// The Panda cube world compiled, with a trial plan lifting it 10 cm.
struct CubeTrial {
  CubeTrial() {
    const ObjectBody body{collisionPieces(test::smallCube()),
                          objectMassProperties(test::smallCube(), 1000.0), world.scene.target_pose};
    ModelSettings settings;
    settings.torsional_friction = test::panda().torsionalFriction();
    model = compileMjcf(mjcfScene(test::panda(), world.scene, body, settings));
    plan.robot = &test::panda();
    plan.index = indexWorld(*model, test::panda());
    plan.pregrasp = world.pregrasp;
    plan.grasp = world.grasp;
    plan.close_limit = closeLimits(test::panda(), world.pregrasp, world.grasp);
    plan.close_lead = closeLeads(test::panda());
    plan.lift =
        planLift(test::collisionOf(test::panda()), world.scene, world.grasp, 0.1).line.waypoints;
    plan.object_pose = world.scene.target_pose;
    plan.options.disturbance_time = 0.0;
    plan.options.hold_time = 0.5;
  }
  test::PandaCube world;
  ModelPtr model;
  TrialPlan plan;
};

TEST(GraspTrial, TheHandCloseTargetRunsOnToTheJointLimitInTheClosingDirection) {
  const test::PandaCube world;
  // The Panda's jaw closes towards 0, its lower limit.
  EXPECT_EQ(closeLimits(test::panda(), world.pregrasp, world.grasp)(0), 0.0);
  // The SDH: flexing closes towards the upper limit; an unmoved DoF (the
  // knuckle) stays where the grasp has it; an opening one goes to the lower.
  const robot::RobotModel& sdh = test::kr5Sdh();
  Eigen::VectorXd pregrasp = sdh.home(), grasp = sdh.home();
  grasp(6) = pregrasp(6) = 0.3;
  grasp(7) += 0.1;
  grasp(8) -= 0.1;
  const Eigen::VectorXd limits = closeLimits(sdh, pregrasp, grasp);
  EXPECT_EQ(limits(0), 0.3);
  EXPECT_EQ(limits(1), sdh.upperLimits()(7));
  EXPECT_EQ(limits(2), sdh.lowerLimits()(8));
  EXPECT_EQ(limits(3), grasp(9));
}

TEST(GraspTrial, AClosingTargetLeadsItsJointByTwiceEffortOverStiffness) {
  // The Panda's one DoF: 2 x 70 N / 5000 N/m = 28 mm; the SDH's distal
  // joints 2 x 1.4 N m / 100 N m/rad = 0.028 rad.
  EXPECT_DOUBLE_EQ(closeLeads(test::panda())(0), 0.028);
  EXPECT_DOUBLE_EQ(closeLeads(test::kr5Sdh())(2), 0.028);
  EXPECT_DOUBLE_EQ(closeLeads(test::kr5Sdh())(1), 0.042);
}

TEST(GraspTrial, APerturbedModelScalesFrictionObjectMassAndHandGainsOnly) {
  const CubeTrial t;
  const Perturbation p{"all", 0.5, 2.0, 3.0};
  const ModelPtr changed = perturbedModel(*t.model, t.plan.index, 7, p);
  const mjModel& a = *t.model;
  const mjModel& b = *changed;
  for (int g = 0; g < a.ngeom; ++g) {
    EXPECT_DOUBLE_EQ(b.geom_friction[3 * g], 0.5 * a.geom_friction[3 * g]);
    EXPECT_DOUBLE_EQ(b.geom_friction[3 * g + 1], 0.5 * a.geom_friction[3 * g + 1]);
  }
  const int object = t.plan.index.object_body;
  EXPECT_DOUBLE_EQ(b.body_mass[object], 2.0 * a.body_mass[object]);
  EXPECT_DOUBLE_EQ(b.body_inertia[3 * object], 2.0 * a.body_inertia[3 * object]);
  const int jaw = t.plan.index.actuator[7];
  EXPECT_DOUBLE_EQ(b.actuator_gainprm[jaw * mjNGAIN], 3.0 * a.actuator_gainprm[jaw * mjNGAIN]);
  EXPECT_DOUBLE_EQ(b.actuator_biasprm[jaw * mjNBIAS + 1],
                   3.0 * a.actuator_biasprm[jaw * mjNBIAS + 1]);
  const int shoulder = t.plan.index.actuator[0];
  EXPECT_EQ(b.actuator_gainprm[shoulder * mjNGAIN], a.actuator_gainprm[shoulder * mjNGAIN]);
  EXPECT_EQ(b.body_mass[1], a.body_mass[1]);  // the robot's base
}

TEST(GraspTrial, TheClosedHandCarriesTheCubeAndTheMotionFollowsThePhases) {
  CubeTrial t;
  std::vector<MotionSample> motion;
  const TrialResult r = runTrial(*t.model, t.plan, "nominal", &motion);
  EXPECT_TRUE(r.held) << r.failure;
  EXPECT_EQ(r.name, "nominal");
  EXPECT_EQ(r.fingers_in_contact, 2);
  EXPECT_LT(r.max_displacement, 0.002);
  std::vector<std::string> phases;
  for (const MotionSample& s : motion)
    if (phases.empty() || phases.back() != s.phase) phases.push_back(s.phase);
  EXPECT_EQ(phases, (std::vector<std::string>{"settle", "close", "lift", "hold"}));
  // 50 samples per second over 0.3 + 1 + 1 + 0.5 s.
  EXPECT_NEAR(static_cast<double>(motion.size()), 140.0, 1.0);
}

TEST(GraspTrial, AnObjectStillOnItsSupportAfterTheLiftFails) {
  CubeTrial t;
  t.plan.lift = {t.world.grasp};  // the arm does not move
  const TrialResult r = runTrial(*t.model, t.plan, "nominal");
  EXPECT_FALSE(r.held);
  EXPECT_EQ(r.failure, "lift: object still touches 'table' after the lift");
}

TEST(GraspTrial, TheDisturbancesEachStartFromTheHeldState) {
  CubeTrial t;
  t.plan.options.disturbance_time = 0.1;
  std::vector<MotionSample> motion;
  const TrialResult r = runTrial(*t.model, t.plan, "nominal", &motion);
  EXPECT_TRUE(r.held) << r.failure;
  EXPECT_EQ(motion.back().phase, "disturbance -z");
  // The samples' times run on across the six disturbances.
  EXPECT_NEAR(motion.back().time, 0.3 + 1 + 1 + 0.5 + 6 * 0.1, 0.03);
}

}  // namespace
}  // namespace hfts::physics
