#include "robot/robot_model.h"

#include <gtest/gtest.h>

#include <tuple>
#include <vector>

#include "robot/kinematics.h"

#include "robot_fixture.h"
#include "test_meshes.h"

namespace hfts::robot {
namespace {

TEST(RobotModel, Kr5SdhHas13ActuatedDofInConfigOrder) {
  const RobotModel& m = test::kr5Sdh();
  EXPECT_EQ(m.numDofs(), 13);
  EXPECT_EQ(m.numArmDofs(), 6);
  EXPECT_EQ(m.numHandDofs(), 7);
  EXPECT_EQ(m.dofNames().front(), "a1");
  EXPECT_EQ(m.dofNames()[6], "knuckle");
  EXPECT_EQ(m.dofNames().back(), "thumb_distal_joint");
  EXPECT_EQ(m.fingertips().size(), 3u);
  EXPECT_NEAR(m.lowerLimits()(0), -170.0 * M_PI / 180.0, 1e-9);
  EXPECT_NEAR(m.upperLimits()(5), 358.0 * M_PI / 180.0, 1e-9);
  EXPECT_NEAR(m.maxVelocities()(0), 375.0 * M_PI / 180.0, 1e-9);
  ASSERT_EQ(m.maxAccelerations().size(), 13);
  EXPECT_DOUBLE_EQ(m.maxAccelerations()(0), 8.0);
  EXPECT_DOUBLE_EQ(m.maxAccelerations()(12), 5.0);
  EXPECT_DOUBLE_EQ(m.dofWeights()(0), 1.0);
  EXPECT_DOUBLE_EQ(m.dofWeights()(12), 0.25);
  EXPECT_TRUE(m.withinLimits(m.home()));
}

TEST(RobotModel, HalfExtentsBoundEachShapeInItsOwnFrame) {
  CollisionShape box{CollisionShape::Type::kBox, Eigen::Vector3d(0.2, 0.4, 0.6)};
  CollisionShape cylinder{CollisionShape::Type::kCylinder, Eigen::Vector3d(0.05, 0.3, 0)};
  CollisionShape sphere{CollisionShape::Type::kSphere, Eigen::Vector3d(0.07, 0, 0)};
  EXPECT_TRUE(halfExtents(box).isApprox(Eigen::Vector3d(0.1, 0.2, 0.3)));
  EXPECT_TRUE(halfExtents(cylinder).isApprox(Eigen::Vector3d(0.05, 0.05, 0.15)));
  EXPECT_TRUE(halfExtents(sphere).isApprox(Eigen::Vector3d::Constant(0.07)));
}

TEST(RobotModel, TheKnuckleMimicFollowsTheKnuckle) {
  const RobotModel& m = test::kr5Sdh();
  int mimics = 0;
  for (const Joint& j : m.joints()) {
    if (j.name != "knuckle_mimic") continue;
    EXPECT_EQ(m.dofNames()[static_cast<std::size_t>(j.dof)], "knuckle");
    EXPECT_DOUBLE_EQ(j.multiplier, 1.0);
    ++mimics;
  }
  EXPECT_EQ(mimics, 1);
}

TEST(RobotModel, LinksAreTopologicalAndTheHandIsMarked) {
  const RobotModel& m = test::kr5Sdh();
  EXPECT_EQ(m.links()[0].name, "base_link");
  for (const Joint& j : m.joints()) EXPECT_LT(j.parent_link, j.child_link);
  EXPECT_TRUE(m.isHandLink(m.linkIndex("thumb_distal")));
  EXPECT_TRUE(m.isHandLink(m.palmLink()));
  EXPECT_FALSE(m.isHandLink(m.linkIndex("link_6")));
  EXPECT_TRUE(m.isCollisionDisabled(m.linkIndex("link_1"), m.linkIndex("base_link")));
  EXPECT_FALSE(m.isCollisionDisabled(m.linkIndex("base_link"), m.linkIndex("thumb_distal")));
  EXPECT_THROW(m.linkIndex("no_such_link"), ModelError);
}

TEST(RobotModel, WithinLimitsNamesTheViolation) {
  const RobotModel& m = test::kr5Sdh();
  Eigen::VectorXd q = m.home();
  q(1) = 2.0;  // a2 allows at most 45 deg
  std::string why;
  EXPECT_FALSE(m.withinLimits(q, 1e-9, &why));
  EXPECT_NE(why.find("'a2'"), std::string::npos) << why;
  EXPECT_FALSE(m.withinLimits(Eigen::VectorXd::Zero(12), 1e-9, &why));
  q = m.home();
  q(3) = std::nan("");
  EXPECT_FALSE(m.withinLimits(q));
}

struct Sources {
  std::string urdf = test::readBytes(test::sourcePath("robots/kr5_sdh/kr5_sdh.urdf"));
  std::string config = test::readBytes(test::sourcePath("robots/kr5_sdh/kr5_sdh.json"));
};

void expectModelError(const std::string& urdf, const std::string& config,
                      const std::string& problem) {
  test::expectErrorMentioning<ModelError>(
      [&] { RobotModel::fromStrings(urdf, config, "robot 'x'"); }, {"robot 'x'", problem});
}

void replaceOnce(std::string& text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
}

TEST(RobotModel, ConfigThatDoesNotMatchTheUrdfGivesClearErrors) {
  Sources s;
  std::string config = s.config;
  replaceOnce(config, "\"a6\"]", "\"a7\"]");
  expectModelError(s.urdf, config, "robot 'x': arm_joints: joint 'a7' is not in the URDF");
  config = s.config;
  replaceOnce(config, "\"palm_link\": \"palm\"", "\"palm_link\": \"hand\"");
  expectModelError(s.urdf, config, "robot 'x': palm_link: names link 'hand'");
  config = s.config;
  replaceOnce(config, "\"link\": \"finger_1_distal\"", "\"link\": \"finger_9\"");
  expectModelError(s.urdf, config, ".link: names unknown link 'finger_9'");
  expectModelError(s.urdf, config, "robot 'x': fingertips[");
  config = s.config;
  replaceOnce(config, "\"pregrasp_offset\": 0.1,", "");
  expectModelError(s.urdf, config, "robot 'x': pregrasp_offset: is required");
  config = s.config;
  replaceOnce(config, "\"max_accelerations\": [8,", "\"max_accelerations\": [0,");
  expectModelError(s.urdf, config, "robot 'x': max_accelerations: must be positive");
  config = s.config;
  replaceOnce(config, "\"max_accelerations\": [8,", "\"max_accelerations\": [");
  expectModelError(s.urdf, config, "robot 'x': max_accelerations: ");
  std::string slow = s.urdf;
  replaceOnce(slow, "velocity=\"6.544984694978735\"", "velocity=\"0\"");
  expectModelError(slow, s.config, "joint 'a1' needs a positive velocity limit");
  config = s.config;
  replaceOnce(config, "\"home\": [0,", "\"home\": [9,");
  expectModelError(s.urdf, config, "robot 'x': home: value 9");
  expectModelError(s.urdf, "{not json", "not valid JSON");
  expectModelError("<robot name='broken'><link name='a'/>", s.config, "URDF cannot be parsed");
  std::string urdf = s.urdf;
  replaceOnce(urdf, "<mimic joint=\"knuckle\"", "<nomimic joint=\"knuckle\"");
  expectModelError(urdf, s.config, "'knuckle_mimic' is movable but neither listed");
}

TEST(RobotModel, AnArmWithoutAHandHoldsItsOtherJoints) {
  // robots/kr5_sdh/kr5_arm_only.json: the KR5 with the SDH held rigid at
  // the full model's home posture.
  const RobotModel arm = RobotModel::load(test::sourcePath("robots/kr5_sdh/kr5_arm_only.json"));
  const RobotModel& full = test::kr5Sdh();
  EXPECT_FALSE(arm.hasHand());
  EXPECT_TRUE(full.hasHand());
  EXPECT_EQ(arm.numDofs(), 6);
  EXPECT_EQ(arm.numHandDofs(), 0);
  EXPECT_TRUE(arm.fingertips().empty());
  EXPECT_EQ(arm.handOpen().size(), 0);
  EXPECT_EQ(arm.palmLink(), arm.flangeLink()) << "no palm_link: the flange";
  for (std::size_t l = 0; l < arm.links().size(); ++l) EXPECT_FALSE(arm.isHandLink(int(l)));
  // Every link where the full model puts it with the hand at its home.
  Eigen::VectorXd q = full.home();
  const double values[] = {0.3, -1.1, 1.2, 0.4, 1.0, -0.7};
  for (int d = 0; d < 6; ++d) q(d) = values[d];
  const LinkPoses a = forwardKinematics(arm, q.head(6));
  const LinkPoses f = forwardKinematics(full, q);
  ASSERT_EQ(a.size(), f.size());
  for (std::size_t l = 0; l < a.size(); ++l)
    EXPECT_TRUE(a[l].isApprox(f[l], 1e-12)) << full.links()[l].name;
}

TEST(RobotModel, HeldJointsAreChecked) {
  Sources s;
  const std::string config = test::readBytes(test::sourcePath("robots/kr5_sdh/kr5_arm_only.json"));
  const std::string knuckle = "\"knuckle\": 0,";
  // (what the config says instead, the error it gives)
  const std::vector<std::tuple<std::string, std::string, std::string>> edits = {
      {knuckle, "\"knuckle\": 9,", "robot 'x': fixed_joints.knuckle: outside the joint's limits"},
      {knuckle, "\"knuckle\": \"open\",", "fixed_joints.knuckle: must be a finite number"},
      {knuckle, knuckle + " \"a1\": 0,", "fixed_joints.a1: the joint is listed in arm_joints"},
      {knuckle, knuckle + " \"wrist\": 0,", "fixed_joints.wrist: is not a joint of the URDF"},
      {knuckle, "", "joint 'knuckle' is movable but neither listed"},
      {"\"fixed_joints\": {", "\"fingertips\": [], \"fixed_joints\": {",
       "fingertips: need hand_joints"}};
  for (const auto& [from, to, error] : edits) {
    std::string c = config;
    replaceOnce(c, from, to);
    expectModelError(s.urdf, c, error);
  }
}

TEST(RobotModel, AnSrdfsDisabledPairsJoinTheConfigs) {
  const std::string dir = "robots/panda_mbm/";
  const std::string urdf = test::readBytes(test::sourcePath(dir + "panda_spherized.urdf"));
  const std::string config = test::readBytes(test::sourcePath(dir + "panda_mbm.json"));
  const std::string srdf = test::readBytes(test::sourcePath(dir + "panda.srdf"));
  const RobotModel m = RobotModel::fromStrings(urdf, config, "panda", srdf);
  EXPECT_EQ(m.disabledCollisions().size(), 34u);
  const auto fails = [&](const std::string& text, const std::string& problem) {
    test::expectErrorMentioning<ModelError>(
        [&] { RobotModel::fromStrings(urdf, config, "robot 'x'", text); },
        {"robot 'x': srdf: ", problem});
  };
  fails("", "names an SRDF whose text was not given");
  fails("<robot><disable_collisions link1=\"panda_link0\" link2=\"wrist\"/></robot>",
        "names link 'wrist', which is not in the URDF");
  fails("<robot><disable_collisions link1=\"panda_link0\"/></robot>", "without link1 and link2");
  fails("not xml", "cannot be parsed");
  const RobotModel one = RobotModel::fromStrings(
      urdf, config, "one",
      "<robot><disable_collisions link1=\"panda_link0\" link2=\"panda_link1\"/></robot>");
  EXPECT_EQ(one.disabledCollisions().size(), 1u);
}

TEST(RobotModel, ContactModelIsHardFingersUnlessTheConfigSaysSoft) {
  Sources s;
  EXPECT_EQ(RobotModel::fromStrings(s.urdf, s.config, "kr5").torsionalFriction(), 0.0);
  std::string config = s.config;
  replaceOnce(config, "\"pregrasp_offset\"",
              "\"contact_model\": \"soft_finger\", \"torsional_friction\": 0.004, "
              "\"pregrasp_offset\"");
  EXPECT_EQ(RobotModel::fromStrings(s.urdf, config, "soft").torsionalFriction(), 0.004);
  config = s.config;
  replaceOnce(config, "\"pregrasp_offset\"", "\"contact_model\": \"soft\", \"pregrasp_offset\"");
  expectModelError(s.urdf, config, "robot 'x': contact_model: must be \"hard_finger\" or");
  config = s.config;
  replaceOnce(config, "\"pregrasp_offset\"",
              "\"contact_model\": \"soft_finger\", \"pregrasp_offset\"");
  expectModelError(s.urdf, config, "robot 'x': torsional_friction: is required");
  config = s.config;
  replaceOnce(config, "\"pregrasp_offset\"",
              "\"contact_model\": \"soft_finger\", \"torsional_friction\": -1, "
              "\"pregrasp_offset\"");
  expectModelError(s.urdf, config, "robot 'x': torsional_friction: must be > 0");
  config = s.config;
  replaceOnce(config, "\"pregrasp_offset\"", "\"torsional_friction\": 0.01, \"pregrasp_offset\"");
  expectModelError(s.urdf, config, "torsional_friction: applies only to");
}

TEST(RobotModel, HandMapNormalWeightIsOptionalAndPositive) {
  Sources s;
  EXPECT_EQ(RobotModel::fromStrings(s.urdf, s.config, "kr5").handMapNormalWeight(), 0.0);
  std::string config = s.config;
  replaceOnce(config, "\"pregrasp_offset\"",
              "\"hand_map_normal_weight\": 0.005, \"pregrasp_offset\"");
  EXPECT_EQ(RobotModel::fromStrings(s.urdf, config, "w").handMapNormalWeight(), 0.005);
  config = s.config;
  replaceOnce(config, "\"pregrasp_offset\"", "\"hand_map_normal_weight\": 0, \"pregrasp_offset\"");
  expectModelError(s.urdf, config, "robot 'x': hand_map_normal_weight: must be > 0");
}

TEST(RobotModel, PlannerDefaultsAreTextByNameAndNeedNumbersOrStrings) {
  Sources s;
  // The bundled KR5 sets an 8 mm fingertip tolerance.
  EXPECT_EQ(RobotModel::fromStrings(s.urdf, s.config, "kr5").plannerDefaults(),
            (std::map<std::string, std::string>{{"max_fingertip_error", "0.008"}}));
  std::string plain = s.config;
  replaceOnce(plain, "\"planner_defaults\": {\"max_fingertip_error\": 0.008},", "");
  EXPECT_TRUE(RobotModel::fromStrings(s.urdf, plain, "kr5").plannerDefaults().empty());
  std::string config = plain;
  replaceOnce(config, "\"pregrasp_offset\"",
              "\"planner_defaults\": {\"other_postures\": 0, \"p_max\": 0.75, \"kappa\": \"3\"}, "
              "\"pregrasp_offset\"");
  const RobotModel m = RobotModel::fromStrings(s.urdf, config, "d");
  EXPECT_EQ(m.plannerDefaults(), (std::map<std::string, std::string>{
                                     {"kappa", "3"}, {"other_postures", "0"}, {"p_max", "0.75"}}));
  config = plain;
  replaceOnce(config, "\"pregrasp_offset\"",
              "\"planner_defaults\": {\"p_max\": [1]}, \"pregrasp_offset\"");
  expectModelError(s.urdf, config, "robot 'x': planner_defaults.p_max: must be a finite number");
  config = plain;
  replaceOnce(config, "\"pregrasp_offset\"", "\"planner_defaults\": 1, \"pregrasp_offset\"");
  expectModelError(s.urdf, config, "robot 'x': planner_defaults: must be an object");
}

TEST(RobotModel, EveryBundledRobotHasItsHandsEffortsWithTheirSource) {
  for (const char* name : {"kr5_sdh", "panda_gripper", "ur5e_allegro"}) {
    const RobotModel m =
        RobotModel::load(test::sourcePath(std::string("robots/") + name + "/" + name + ".json"));
    ASSERT_TRUE(m.handActuation()) << name;
    EXPECT_EQ(m.handActuation()->efforts.size(), m.numHandDofs()) << name;
    EXPECT_GT(m.handActuation()->kp, 0.0) << name;
    EXPECT_FALSE(m.handActuation()->source.empty()) << name;
  }
  // The SDH: 2.1 N m at the knuckle and the proximal joints, 1.4 N m distal.
  Eigen::VectorXd sdh(7);
  sdh << 2.1, 2.1, 1.4, 2.1, 1.4, 2.1, 1.4;
  EXPECT_EQ(test::kr5Sdh().handActuation()->efforts, sdh);
}

TEST(RobotModel, HandActuationErrorsNameTheKey) {
  Sources s;
  const std::string efforts = "\"efforts\": [2.1, 2.1, 1.4, 2.1, 1.4, 2.1, 1.4]";
  std::string config = s.config;
  replaceOnce(config, efforts, "\"efforts\": [2.1, 2.1]");
  expectModelError(s.urdf, config, "robot 'x': hand_actuation.efforts: ");
  config = s.config;
  replaceOnce(config, efforts, "\"efforts\": [2.1, 2.1, 1.4, 2.1, 1.4, 2.1, -1]");
  expectModelError(s.urdf, config, "robot 'x': hand_actuation.efforts: must be positive");
  config = s.config;
  replaceOnce(config, "\"kp\": 100", "\"kp\": 0");
  expectModelError(s.urdf, config, "robot 'x': hand_actuation.kp: must be > 0");
  config = s.config;
  replaceOnce(config, "\"kv\": 1.0", "\"kv\": \"fast\"");
  expectModelError(s.urdf, config, "robot 'x': hand_actuation.kv: must be a finite number");
  config = s.config;
  replaceOnce(config, "\"kv\": 1.0,", "");
  expectModelError(s.urdf, config, "robot 'x': hand_actuation.kv: is required");
  config = s.config;
  replaceOnce(config, "\"hand_actuation\": {", "\"hand_actuation\": 1, \"unused\": {");
  expectModelError(s.urdf, config, "robot 'x': hand_actuation: must be an object");
  config = s.config;
  replaceOnce(config, "\"hand_actuation\"", "\"no_actuation\"");
  EXPECT_FALSE(RobotModel::fromStrings(s.urdf, config, "kr5").handActuation());
}

TEST(RobotModel, UrdfInertialsAndEffortsAreKept) {
  const RobotModel& kr5 = test::kr5Sdh();
  const Link& palm = kr5.links()[static_cast<std::size_t>(kr5.palmLink())];
  ASSERT_TRUE(palm.inertial);
  EXPECT_EQ(palm.inertial->mass, 1.3);
  EXPECT_TRUE(palm.inertial->origin.translation().isApprox(Eigen::Vector3d(-0.01, 0, 0.036)));
  EXPECT_EQ(palm.inertial->inertia(1, 1), 0.00205);
  EXPECT_EQ(palm.inertial->inertia(0, 1), 0.0);
  EXPECT_EQ(kr5.joints()[0].effort, 100.0);  // a1, nominal
  const RobotModel panda =
      RobotModel::load(test::sourcePath("robots/panda_gripper/panda_gripper.json"));
  EXPECT_FALSE(panda.links()[0].inertial);  // the Panda's URDF gives none
  Sources s;
  std::string urdf = s.urdf;
  replaceOnce(urdf, "<mass value=\"1.3\"/>", "<mass value=\"0\"/>");
  expectModelError(urdf, s.config, "link 'palm': <inertial> needs a positive mass");
}

TEST(RobotModel, MissingFilesAreNamed) {
  test::expectErrorMentioning<ModelError>([] { RobotModel::load("/nonexistent/robot.json"); },
                                          {"/nonexistent/robot.json"});
}

}  // namespace
}  // namespace hfts::robot
