#include "physics/mjcf_scene.h"

#include <gtest/gtest.h>

#include "core/invalid_argument.h"
#include "mujoco_world.h"
#include "panda_cube.h"
#include "robot/point_cloud.h"

namespace hfts::physics {
namespace {

ObjectBody cubeBody(const test::PandaCube& world) {
  return {collisionPieces(test::smallCube()), objectMassProperties(test::smallCube(), 1000.0),
          world.scene.target_pose};
}

int count(const mjModel& m, mjtObj type, const std::string& prefix) {
  int n = 0;
  const int total = type == mjOBJ_BODY ? m.nbody : type == mjOBJ_GEOM ? m.ngeom : m.neq;
  for (int i = 0; i < total; ++i) {
    const char* name = mj_id2name(&m, type, i);
    if (name != nullptr && std::string(name).rfind(prefix, 0) == 0) ++n;
  }
  return n;
}

TEST(MjcfScene, ThePandaSceneHasOneBodyPerLinkOneServoPerDofAndItsMimicAsAnEquality) {
  const test::PandaCube world;
  const robot::RobotModel& panda = test::panda();
  const ModelPtr model = compileMjcf(mjcfScene(panda, world.scene, cubeBody(world)));
  const mjModel& m = *model;
  // The world, 12 links (panda_link0 .. 8, the hand, two fingers) and the object.
  EXPECT_EQ(m.nbody, 1 + static_cast<int>(panda.links().size()) + 1);
  EXPECT_EQ(count(m, mjOBJ_BODY, kRobotPrefix), 12);
  EXPECT_EQ(m.nu, panda.numDofs());
  EXPECT_EQ(m.nu, 8);
  // 8 DoF joints, the mimicking jaw and the object's free joint.
  EXPECT_EQ(m.njnt, 10);
  ASSERT_EQ(m.neq, 1);
  EXPECT_EQ(m.eq_type[0], mjEQ_JOINT);
  EXPECT_EQ(std::string(mj_id2name(&m, mjOBJ_JOINT, m.eq_obj1id[0])), "robot/panda_finger_joint2");
  EXPECT_EQ(std::string(mj_id2name(&m, mjOBJ_JOINT, m.eq_obj2id[0])), "robot/panda_finger_joint1");
  EXPECT_EQ(m.eq_data[0], 0.0);  // polycoef: offset, then multiplier
  EXPECT_EQ(m.eq_data[1], 1.0);
  EXPECT_EQ(count(m, mjOBJ_GEOM, "obstacle/"), 1);
}

TEST(MjcfScene, TheHandServosPressWithTheConfigsEffortAndTheArmServosAreStiff) {
  const test::PandaCube world;
  const robot::RobotModel& panda = test::panda();
  const ModelPtr model = compileMjcf(mjcfScene(panda, world.scene, cubeBody(world)));
  const WorldIndex index = indexWorld(*model, panda);
  const int hand = index.actuator[7];
  EXPECT_EQ(model->actuator_forcelimited[hand], 1);
  EXPECT_EQ(model->actuator_forcerange[2 * hand + 1], 70.0);
  EXPECT_EQ(model->actuator_gainprm[hand * mjNGAIN], panda.handActuation()->kp);
  EXPECT_EQ(model->dof_damping[index.dof_velocity[7]], panda.handActuation()->kv);
  const int shoulder = index.actuator[0];
  EXPECT_EQ(model->actuator_forcelimited[shoulder], 0);
  EXPECT_EQ(model->actuator_gainprm[shoulder * mjNGAIN], ModelSettings{}.arm_kp);
  EXPECT_NEAR(model->dof_armature[index.dof_velocity[0]], servoArmature(20000.0, 0.002), 1e-12);
}

TEST(MjcfScene, TheObjectIsAFreeBodyWithItsMassAndInertia) {
  const test::PandaCube world;
  const ObjectBody body = cubeBody(world);
  const ModelPtr model = compileMjcf(mjcfScene(test::panda(), world.scene, body));
  const int object = mj_name2id(model.get(), mjOBJ_BODY, kObjectBodyName);
  ASSERT_GE(object, 0);
  EXPECT_NEAR(model->body_mass[object], body.mass.mass, 1e-12);
  // A cube's principal moments are all m a^2 / 6.
  const double moment = body.mass.mass * 0.046 * 0.046 / 6.0;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(model->body_inertia[3 * object + k], moment, 1e-9);
  EXPECT_NEAR(model->body_ipos[3 * object + 2], 0.023, 1e-9);  // the centre, above the origin
  EXPECT_EQ(model->jnt_type[model->body_jntadr[object]], mjJNT_FREE);
}

TEST(MjcfScene, LinksWithoutInertialWeighTheirShapesAndUrdfInertialsAreKept) {
  const test::PandaCube world;
  const ModelPtr panda = compileMjcf(mjcfScene(test::panda(), world.scene, cubeBody(world)));
  // The Franka hand's box (0.06 x 0.2 x 0.06 m) at 1000 kg/m^3: 0.72 kg,
  // as Franka publishes 0.73 kg.
  EXPECT_NEAR(panda->body_mass[mj_name2id(panda.get(), mjOBJ_BODY, "robot/panda_hand")], 0.72,
              1e-9);
  const robot::RobotModel& kr5 = test::kr5Sdh();
  const ModelPtr sdh = compileMjcf(mjcfScene(kr5, world.scene, cubeBody(world)));
  EXPECT_NEAR(sdh->body_mass[mj_name2id(sdh.get(), mjOBJ_BODY, "robot/palm")], 1.3, 1e-12);
  // The SDH knuckle mimic: one equality, finger 2's base following the knuckle.
  ASSERT_EQ(sdh->neq, 1);
  EXPECT_EQ(std::string(mj_id2name(sdh.get(), mjOBJ_JOINT, sdh->eq_obj2id[0])), "robot/knuckle");
  EXPECT_EQ(sdh->nu, 13);
}

TEST(MjcfScene, SoftFingerPadsGetTorsionalFrictionAndHardOnesDoNot) {
  const test::PandaCube world;
  ModelSettings settings;
  settings.torsional_friction = 0.003;
  const ModelPtr model =
      compileMjcf(mjcfScene(test::panda(), world.scene, cubeBody(world), settings));
  const int left = mj_name2id(model.get(), mjOBJ_BODY, "robot/panda_leftfinger");
  const int hand = mj_name2id(model.get(), mjOBJ_BODY, "robot/panda_hand");
  for (int g = 0; g < model->ngeom; ++g) {
    if (model->geom_bodyid[g] == left) {
      EXPECT_EQ(model->geom_condim[g], 4);
      EXPECT_EQ(model->geom_friction[3 * g + 1], 0.003);
    }
    if (model->geom_bodyid[g] == hand) {
      EXPECT_EQ(model->geom_condim[g], 3);
    }
  }
}

TEST(MjcfScene, ACloudStaysOutAndAPlateStandsUnderTheObject) {
  test::PandaCube world;
  const ObjectBody body = cubeBody(world);
  const ModelPtr plain = compileMjcf(mjcfObjectScene(world.scene, body));
  EXPECT_EQ(count(*plain, mjOBJ_GEOM, "obstacle/sensed_support"), 0);
  robot::Obstacle seen;
  seen.name = "seen";
  seen.type = robot::Obstacle::Type::kPoints;
  Vertices points(2, 3);
  points << 0.3, 0.3, 0.0, 0.5, 0.3, 0.0;
  seen.cloud = std::make_shared<robot::VoxelCloud>(robot::voxelize(points));
  world.scene.obstacles.push_back(seen);
  const ModelPtr sensed = compileMjcf(mjcfObjectScene(world.scene, body));
  EXPECT_EQ(count(*sensed, mjOBJ_GEOM, "obstacle/seen"), 0);
  const int plate = mj_name2id(sensed.get(), mjOBJ_GEOM, "obstacle/sensed_support");
  ASSERT_GE(plate, 0);
  // Its top 1 mm under the cube's bottom (the cube's frame at its bottom face).
  const double top = sensed->geom_pos[3 * plate + 2] + sensed->geom_size[3 * plate + 2];
  EXPECT_NEAR(top, world.scene.target_pose.translation().z() - robot::kRestingClearance, 1e-9);
  EXPECT_EQ(count(*sensed, mjOBJ_GEOM, "obstacle/"), count(*plain, mjOBJ_GEOM, "obstacle/") + 1);
}

TEST(MjcfScene, ARobotWithoutHandActuationIsRefused) {
  const std::string urdf = test::readBytes(test::sourcePath("robots/kr5_sdh/kr5_sdh.urdf"));
  std::string config = test::readBytes(test::sourcePath("robots/kr5_sdh/kr5_sdh.json"));
  config.replace(config.find("\"hand_actuation\""), 16, "\"no_actuation\"");
  const robot::RobotModel bare = robot::RobotModel::fromStrings(urdf, config, "bare");
  const test::PandaCube world;
  EXPECT_THROW(mjcfScene(bare, world.scene, cubeBody(world)), InvalidArgument);
}

}  // namespace
}  // namespace hfts::physics
