#include "robot/arm_ik.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "robot/kinematics.h"
#include "robot_fixture.h"
#include "test_meshes.h"

namespace hfts::robot {
namespace {

const RobotModel& kr5() {
  static const RobotModel model =
      RobotModel::load(std::filesystem::path(HFTS_SOURCE_DIR) / "robots/kr5_sdh/kr5_sdh.json");
  return model;
}

const RobotModel& panda() {
  static const RobotModel model = RobotModel::load(std::filesystem::path(HFTS_SOURCE_DIR) /
                                                   "robots/panda_gripper/panda_gripper.json");
  return model;
}

Eigen::VectorXd randomArm(const RobotModel& model, std::mt19937_64& rng) {
  Eigen::VectorXd arm(model.numArmDofs());
  for (int d = 0; d < model.numArmDofs(); ++d)
    arm(d) =
        std::uniform_real_distribution<double>(model.lowerLimits()(d), model.upperLimits()(d))(rng);
  return arm;
}

double poseError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return std::max((a.translation() - b.translation()).norm(),
                  Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle());
}

bool contains(const std::vector<Eigen::VectorXd>& solutions, const Eigen::VectorXd& arm,
              double tolerance) {
  for (const Eigen::VectorXd& s : solutions)
    if ((s - arm).cwiseAbs().maxCoeff() < tolerance) return true;
  return false;
}

TEST(ArmIk, Kr5UsesTheClosedForm) {
  EXPECT_TRUE(ArmIk(kr5()).isAnalytic());
}

TEST(ArmIk, EverySolutionReachesThePoseWithinLimitsAndTheSourceIsFound) {
  const ArmIk ik(kr5());
  std::mt19937_64 rng(11);
  std::size_t total = 0;
  for (int i = 0; i < 10000; ++i) {
    const Eigen::VectorXd source = randomArm(kr5(), rng);
    const Eigen::Isometry3d target = ik.flangePose(source);
    const std::vector<Eigen::VectorXd> solutions = ik.solveFlange(target, rng);
    total += solutions.size();
    for (const Eigen::VectorXd& arm : solutions) {
      ASSERT_LT(poseError(ik.flangePose(arm), target), 1e-6) << arm.transpose();
      Eigen::VectorXd q = kr5().home();
      q.head(6) = arm;
      ASSERT_TRUE(kr5().withinLimits(q)) << arm.transpose();
    }
    ASSERT_TRUE(contains(solutions, source, 1e-6)) << "source " << source.transpose();
  }
  EXPECT_GT(total, 40000u);  // several branches per pose
}

TEST(ArmIk, NumericalSolverFindsNothingTheClosedFormMisses) {
  ArmIk ik(kr5());
  ik.options().restarts = 40;
  std::mt19937_64 rng(12);
  std::size_t numerical = 0;
  for (int i = 0; i < 100; ++i) {
    const Eigen::Isometry3d target = ik.flangePose(randomArm(kr5(), rng));
    const std::vector<Eigen::VectorXd> closed = ik.solveFlange(target, rng);
    for (const Eigen::VectorXd& arm : ik.solveNumerically(target, rng)) {
      EXPECT_LT(poseError(ik.flangePose(arm), target), 1e-6);
      EXPECT_TRUE(contains(closed, arm, 1e-5)) << "missed " << arm.transpose();
      ++numerical;
    }
  }
  EXPECT_GT(numerical, 100u);
}

TEST(ArmIk, UnreachablePosesHaveNoSolution) {
  const ArmIk ik(kr5());
  std::mt19937_64 rng(1);
  Eigen::Isometry3d far = Eigen::Isometry3d::Identity();
  far.translation() << 2.0, 0.0, 0.5;
  EXPECT_TRUE(ik.solveFlange(far, rng).empty());
}

TEST(ArmIk, PalmPosesAreSolvedThroughTheFixedAdapter) {
  const ArmIk ik(kr5());
  std::mt19937_64 rng(3);
  const Eigen::VectorXd source = randomArm(kr5(), rng);
  const Eigen::Isometry3d palm = ik.flangePose(source) * ik.palmInFlange();
  const auto solutions = ik.solvePalm(palm, rng);
  EXPECT_TRUE(contains(solutions, source, 1e-6));
  EXPECT_NEAR(ik.palmInFlange().translation().norm(), 0.04, 1e-12);
}

/// The KR5 with axis 6 moved sideways: no longer a spherical wrist.
RobotModel offsetWristRobot() {
  const std::filesystem::path dir = std::filesystem::path(HFTS_SOURCE_DIR) / "robots/kr5_sdh";
  std::string urdf = test::readBytes(dir / "kr5_sdh.urdf");
  const std::string config = test::readBytes(dir / "kr5_sdh.json");
  const auto joint = urdf.find("<joint name=\"a6\"");
  const auto origin = urdf.find("<origin", joint);
  const auto end = urdf.find("/>", origin);
  urdf.replace(origin, end + 2 - origin, "<origin xyz=\"0.080 0.02 0\" rpy=\"0 0 0\"/>");
  return RobotModel::fromStrings(urdf, config, "offset wrist");
}

TEST(ArmIk, ArmsWithoutASphericalWristFallBackToDampedLeastSquares) {
  const RobotModel model = offsetWristRobot();
  ArmIk ik(model);
  EXPECT_FALSE(ik.isAnalytic());
  std::mt19937_64 rng(4);
  for (int i = 0; i < 10; ++i) {
    const Eigen::VectorXd source = randomArm(model, rng);
    const Eigen::Isometry3d target = ik.flangePose(source);
    const auto solutions = ik.solveFlange(target, rng);
    ASSERT_FALSE(solutions.empty());
    for (const auto& arm : solutions) EXPECT_LT(poseError(ik.flangePose(arm), target), 1e-6);
  }
}

// The Panda's 7 DoF: a continuum of solutions per pose. Round trips from
// random configurations: every solution reaches the pose, lies within the
// limits and differs from the others by at least 0.1 rad in some joint.
TEST(ArmIk, SevenDofArmRoundTripsThroughTheNumericalSolver) {
  ArmIk ik(panda());
  EXPECT_FALSE(ik.isAnalytic());
  std::mt19937_64 rng(7);
  int solvedWithSeveral = 0;
  for (int i = 0; i < 20; ++i) {
    const Eigen::VectorXd source = randomArm(panda(), rng);
    const Eigen::Isometry3d target = ik.flangePose(source);
    // The same pose by the model's own forward kinematics.
    Eigen::VectorXd q = panda().home();
    q.head(7) = source;
    EXPECT_LT(
        poseError(forwardKinematics(panda(), q)[static_cast<std::size_t>(panda().flangeLink())],
                  target),
        1e-12);
    const auto solutions = ik.solveFlange(target, rng);
    ASSERT_FALSE(solutions.empty()) << i;
    for (std::size_t a = 0; a < solutions.size(); ++a) {
      ASSERT_EQ(solutions[a].size(), 7);
      EXPECT_LT(poseError(ik.flangePose(solutions[a]), target), 1e-6);
      q.head(7) = solutions[a];
      EXPECT_TRUE(panda().withinLimits(q));
      for (std::size_t b = 0; b < a; ++b)
        EXPECT_GE((solutions[a] - solutions[b]).cwiseAbs().maxCoeff(), 0.1);
    }
    solvedWithSeveral += solutions.size() > 1 ? 1 : 0;
  }
  EXPECT_GE(solvedWithSeveral, 15);  // the redundancy shows
}

/// A UR-type arm from standard DH parameters as Universal Robots publish
/// them (alpha = pi/2, 0, 0, pi/2, -pi/2, 0; joint frames as in their
/// ROS description), with a small two-jaw gripper on the flange.
RobotModel urTypeArm(double d1, double a2, double a3, double d4, double d5, double d6) {
  const auto joint = [](const std::string& name, const std::string& parent,
                        const std::string& child, const std::string& origin) {
    return "<joint name=\"" + name + "\" type=\"revolute\"><parent link=\"" + parent +
           "\"/><child link=\"" + child + "\"/>" + origin +
           "<axis xyz=\"0 0 1\"/><limit lower=\"-6.283185307179586\" "
           "upper=\"6.283185307179586\" velocity=\"3.14\" effort=\"1\"/></joint>";
  };
  const auto xyz = [](double x, double y, double z, const std::string& rpy = "0 0 0") {
    std::ostringstream o;
    o.precision(17);
    o << "<origin xyz=\"" << x << " " << y << " " << z << "\" rpy=\"" << rpy << "\"/>";
    return o.str();
  };
  const std::string half = "1.5707963267948966", pi = "3.141592653589793";
  std::string urdf = "<robot name=\"ur_type\">";
  for (const char* link : {"base", "shoulder", "upper_arm", "forearm", "wrist_1", "wrist_2",
                           "wrist_3", "palm", "left", "right"})
    urdf += "<link name=\"" + std::string(link) + "\"/>";
  urdf += joint("j1", "base", "shoulder", xyz(0, 0, d1)) +
          joint("j2", "shoulder", "upper_arm", xyz(0, 0, 0, half + " 0 0")) +
          joint("j3", "upper_arm", "forearm", xyz(a2, 0, 0)) +
          joint("j4", "forearm", "wrist_1", xyz(a3, 0, d4)) +
          joint("j5", "wrist_1", "wrist_2", xyz(0, -d5, 0, half + " 0 0")) +
          joint("j6", "wrist_2", "wrist_3", xyz(0, d6, 0, half + " " + pi + " " + pi)) +
          "<joint name=\"adapter\" type=\"fixed\"><parent link=\"wrist_3\"/>"
          "<child link=\"palm\"/>" +
          xyz(0, 0, 0.03) +
          "</joint>"
          "<joint name=\"jaw\" type=\"prismatic\"><parent link=\"palm\"/><child link=\"left\"/>" +
          xyz(0, 0, 0.05) +
          "<axis xyz=\"0 1 0\"/><limit lower=\"0\" upper=\"0.04\" velocity=\"0.1\" "
          "effort=\"1\"/></joint>"
          "<joint name=\"jaw_mimic\" type=\"prismatic\"><parent link=\"palm\"/>"
          "<child link=\"right\"/>" +
          xyz(0, 0, 0.05) +
          "<axis xyz=\"0 -1 0\"/><limit lower=\"0\" upper=\"0.04\" velocity=\"0.1\" "
          "effort=\"1\"/><mimic joint=\"jaw\"/></joint></robot>";
  const std::string config = R"({
    "name": "ur_type", "urdf": "ur_type.urdf", "base_link": "base", "flange_link": "wrist_3",
    "palm_link": "palm", "arm_joints": ["j1", "j2", "j3", "j4", "j5", "j6"],
    "hand_joints": ["jaw"],
    "fingertips": [
      {"name": "left", "link": "left", "point": [0, 0, 0.02], "normal": [0, -1, 0]},
      {"name": "right", "link": "right", "point": [0, 0, 0.02], "normal": [0, 1, 0]}],
    "contact_model": "soft_finger", "torsional_friction": 0.003,
    "hand_open": [0.04], "pregrasp_offset": 0.01, "dof_weights": [1, 1, 1, 1, 1, 1, 1],
    "home": [0, -1.5707963267948966, 1.5707963267948966, 0, 0, 0, 0.04],
    "disabled_collisions": [["palm", "left"]]})";
  return RobotModel::fromStrings(urdf, config, "UR-type test arm");
}

/// Round trips from random configurations: every solution reaches the pose
/// within the limits, the source is among them, and damped least squares
/// from many seeds finds nothing else.
void expectClosedFormRoundTrips(const RobotModel& model, std::uint64_t seed) {
  ArmIk ik(model);
  ASSERT_EQ(ik.form(), ArmIk::Form::kThreeParallel);
  std::mt19937_64 rng(seed);
  std::size_t total = 0;
  for (int i = 0; i < 3000; ++i) {
    const Eigen::VectorXd source = randomArm(model, rng);
    const Eigen::Isometry3d target = ik.flangePose(source);
    const std::vector<Eigen::VectorXd> solutions = ik.solveFlange(target, rng);
    total += solutions.size();
    Eigen::VectorXd q = model.home();
    for (const Eigen::VectorXd& arm : solutions) {
      ASSERT_LT(poseError(ik.flangePose(arm), target), 1e-6) << arm.transpose();
      q.head(6) = arm;
      ASSERT_TRUE(model.withinLimits(q)) << arm.transpose();
    }
    ASSERT_TRUE(contains(solutions, source, 1e-6)) << "source " << source.transpose();
    q.head(6) = source;  // the solver's pose is the model's own
    ASSERT_LT(poseError(forwardKinematics(model, q)[static_cast<std::size_t>(model.flangeLink())],
                        target),
              1e-12);
  }
  // Eight branches, each in 2^6 turns within +-2 pi: many per pose.
  EXPECT_GT(total, 3000u * 8);
  ik.options().restarts = 40;
  std::size_t numerical = 0;
  for (int i = 0; i < 50; ++i) {
    const Eigen::Isometry3d target = ik.flangePose(randomArm(model, rng));
    const std::vector<Eigen::VectorXd> closed = ik.solveFlange(target, rng);
    for (const Eigen::VectorXd& arm : ik.solveNumerically(target, rng)) {
      EXPECT_TRUE(contains(closed, arm, 1e-5)) << "missed " << arm.transpose();
      ++numerical;
    }
  }
  EXPECT_GT(numerical, 50u);
}

TEST(ArmIk, UrTypeArmsUseTheirClosedForm) {
  expectClosedFormRoundTrips(urTypeArm(0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996), 21);
  // UR10e, and an arm of the same type with other signs and no shoulder offset.
  expectClosedFormRoundTrips(urTypeArm(0.1807, -0.6127, -0.57155, 0.17415, 0.11985, 0.11655), 22);
  expectClosedFormRoundTrips(urTypeArm(0.3, 0.5, 0.4, 0.0, -0.1, 0.08), 23);
}

TEST(ArmIk, AWristSingularityStillReachesThePose) {
  const RobotModel ur5e = urTypeArm(0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996);
  const ArmIk ik(ur5e);
  std::mt19937_64 rng(5);
  for (const double q5 : {0.0, M_PI}) {  // axis 6 parallel to axes 2-4
    Eigen::VectorXd source(6);
    source << 0.3, -1.2, 1.4, -0.5, q5, 0.7;
    const Eigen::Isometry3d target = ik.flangePose(source);
    const auto solutions = ik.solveFlange(target, rng);
    ASSERT_FALSE(solutions.empty()) << q5;
    for (const Eigen::VectorXd& arm : solutions)
      EXPECT_LT(poseError(ik.flangePose(arm), target), 1e-6);
  }
}

TEST(ArmIk, NearestWholeTurnsMovesEachSolutionToItsNearestInLimitVariantOnce) {
  // Joint 0 turns +-3 pi, joint 1 less than a turn.
  const Eigen::Vector2d lower(-3 * M_PI, -M_PI), upper(3 * M_PI, M_PI);
  const Eigen::Vector2d reference(5.0, 0.0);
  const Eigen::Vector2d a(0.5, 0.2), b(-1.0, 0.3), aNearest(0.5 + 2 * M_PI, 0.2);
  // a's nearest variant is in the list (as a closed form lists it): a goes.
  // b's is not (as a numerical solver may miss it): b is moved there.
  const std::vector<Eigen::VectorXd> kept =
      nearestWholeTurns({a, b, aNearest}, reference, lower, upper);
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_TRUE(kept[0].isApprox(Eigen::Vector2d(-1.0 + 2 * M_PI, 0.3), 1e-12)) << kept[0];
  EXPECT_EQ(kept[1], aNearest);
  // Two solutions of one class, neither nearest: one moved copy.
  const std::vector<Eigen::VectorXd> once =
      nearestWholeTurns({a - Eigen::Vector2d(2 * M_PI, 0), a}, reference, lower, upper);
  ASSERT_EQ(once.size(), 1u);
  EXPECT_TRUE(once[0].isApprox(aNearest, 1e-12));
  // The nearest variant must lie within the limits: 20 rad is beyond 3 pi.
  const std::vector<Eigen::VectorXd> capped =
      nearestWholeTurns({Eigen::Vector2d(-2.0, 0.0)}, Eigen::Vector2d(20.0, 0.0), lower, upper);
  ASSERT_EQ(capped.size(), 1u);
  EXPECT_NEAR(capped[0](0), -2.0 + 2 * M_PI, 1e-12);  // -2 + 4 pi > 3 pi
  EXPECT_LE(capped[0](0), upper(0));
}

TEST(ArmIk, WholeTurnVariantsPutEveryLinkWhereTheirBranchPutsIt) {
  EXPECT_TRUE(differByWholeTurns(Eigen::Vector2d(0.1, -3.0),
                                 Eigen::Vector2d(0.1 + 2 * M_PI, -3.0 - 4 * M_PI)));
  EXPECT_FALSE(differByWholeTurns(Eigen::Vector2d(0.1, -3.0), Eigen::Vector2d(0.1 + M_PI, -3.0)));
  EXPECT_FALSE(differByWholeTurns(Eigen::Vector2d(0.1, -3.0), Eigen::Vector2d(0.1, -3.0 + 1e-6)));
  EXPECT_FALSE(differByWholeTurns(Eigen::Vector2d(0.1, -3.0), Eigen::Vector3d(0.1, -3.0, 0.0)));
  const RobotModel ur5e = RobotModel::load(std::filesystem::path(HFTS_SOURCE_DIR) /
                                           "robots/ur5e_allegro/ur5e_allegro.json");
  const ArmIk ik(ur5e);
  std::mt19937_64 rng(31);
  Eigen::VectorXd source(6);
  source << 2.5, -1.5, 1.2, -1.0, -1.4, 0.3;
  const std::vector<Eigen::VectorXd> solutions = ik.solveFlange(ik.flangePose(source), rng);
  Eigen::VectorXd q = ur5e.home();
  int twins = 0, others = 0;
  for (std::size_t a = 0; a < solutions.size(); ++a)
    for (std::size_t b = a + 1; b < solutions.size(); ++b) {
      q.head(6) = solutions[a];
      const LinkPoses pa = forwardKinematics(ur5e, q);
      q.head(6) = solutions[b];
      const LinkPoses pb = forwardKinematics(ur5e, q);
      double apart = 0;
      for (std::size_t l = 0; l < pa.size(); ++l) apart = std::max(apart, poseError(pa[l], pb[l]));
      if (differByWholeTurns(solutions[a], solutions[b])) {
        ++twins;
        EXPECT_LT(apart, 1e-9);
      } else {
        ++others;
        EXPECT_GT(apart, 1e-6);
      }
    }
  EXPECT_GT(twins, 0);
  EXPECT_GT(others, 0);
}

TEST(ArmIk, ArmsOfFewerThanSixDofAreRefused) {
  std::string config = test::readBytes(test::sourcePath("robots/kr5_sdh/kr5_sdh.json"));
  const auto at = config.find(", \"a6\"]");
  ASSERT_NE(at, std::string::npos);
  config.replace(at, 7, "]");
  const std::string hand = "\"hand_joints\": [";
  config.replace(config.find(hand), hand.size(), hand + "\"a6\", ");
  // a6 counts as a hand DoF now: the open hand and the hand's efforts
  // have one more value.
  const std::string open = "\"hand_open\": [", efforts = "\"efforts\": [";
  config.replace(config.find(open), open.size(), open + "0, ");
  config.replace(config.find(efforts), efforts.size(), efforts + "1, ");
  const RobotModel five = RobotModel::fromStrings(
      test::readBytes(test::sourcePath("robots/kr5_sdh/kr5_sdh.urdf")), config, "five");
  ASSERT_EQ(five.numArmDofs(), 5);
  test::expectErrorMentioning<ModelError>([&] { ArmIk ik(five); }, {"at least 6 DoF", "has 5"});
}

}  // namespace
}  // namespace hfts::robot
