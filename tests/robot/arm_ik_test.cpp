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

TEST(ArmIk, ArmsOfFewerThanSixDofAreRefused) {
  std::string config = test::readBytes(test::sourcePath("robots/kr5_sdh/kr5_sdh.json"));
  const auto at = config.find(", \"a6\"]");
  ASSERT_NE(at, std::string::npos);
  config.replace(at, 7, "]");
  const std::string hand = "\"hand_joints\": [";
  config.replace(config.find(hand), hand.size(), hand + "\"a6\", ");
  // a6 counts as a hand DoF now: the open hand has one more value.
  const std::string open = "\"hand_open\": [";
  config.replace(config.find(open), open.size(), open + "0, ");
  const RobotModel five = RobotModel::fromStrings(
      test::readBytes(test::sourcePath("robots/kr5_sdh/kr5_sdh.urdf")), config, "five");
  ASSERT_EQ(five.numArmDofs(), 5);
  test::expectErrorMentioning<ModelError>([&] { ArmIk ik(five); }, {"at least 6 DoF", "has 5"});
}

}  // namespace
}  // namespace hfts::robot
