#include "robot/kinematics.h"

#include <gtest/gtest.h>

#include <random>

#include "robot_fixture.h"

namespace hfts::robot {
namespace {

const RobotModel& m() {
  return test::kr5Sdh();
}

Eigen::Vector3d linkPosition(const Eigen::VectorXd& q, const std::string& link) {
  return forwardKinematics(m(), q)[static_cast<std::size_t>(m().linkIndex(link))].translation();
}

TEST(Kinematics, ZeroConfigurationStretchesTheArmAlongX) {
  const Eigen::VectorXd q = Eigen::VectorXd::Zero(13);
  const LinkPoses poses = forwardKinematics(m(), q);
  const Eigen::Isometry3d& tool0 = poses[static_cast<std::size_t>(m().flangeLink())];
  EXPECT_TRUE(tool0.translation().isApprox(Eigen::Vector3d(0.925, 0, 0.425), 1e-12));
  EXPECT_TRUE(tool0.linear().col(2).isApprox(Eigen::Vector3d::UnitX(), 1e-12));
  const Eigen::Isometry3d& palm = poses[static_cast<std::size_t>(m().palmLink())];
  EXPECT_TRUE(palm.translation().isApprox(Eigen::Vector3d(0.965, 0, 0.425), 1e-12));
}

TEST(Kinematics, JointOneTurnsAboutMinusZAndJointTwoLiftsTheArm) {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(13);
  q(0) = M_PI / 2;
  EXPECT_TRUE(linkPosition(q, "tool0").isApprox(Eigen::Vector3d(0, -0.925, 0.425), 1e-12));
  q(0) = 0;
  q(1) = -M_PI / 2;  // upper arm straight up
  EXPECT_TRUE(linkPosition(q, "tool0").isApprox(Eigen::Vector3d(-0.015, 0, 1.185), 1e-12));
}

TEST(Kinematics, FingertipsFaceEachOtherWithTheHandStraight) {
  const FingertipFrames tips =
      fingertipFrames(m(), forwardKinematics(m(), Eigen::VectorXd::Zero(13)));
  ASSERT_EQ(tips.positions.cols(), 3);
  // Hand-computed from the SDH geometry (docs/robot.md): palm at (0.965, 0,
  // 0.425) with z along +x; pads 14 mm off the distal axis, 45 mm up.
  EXPECT_TRUE(tips.positions.col(0).isApprox(Eigen::Vector3d(1.1875, 0.033, 0.41995), 1e-9));
  EXPECT_TRUE(tips.positions.col(1).isApprox(Eigen::Vector3d(1.1875, -0.033, 0.41995), 1e-9));
  EXPECT_TRUE(tips.positions.col(2).isApprox(Eigen::Vector3d(1.1875, 0, 0.44911), 1e-9));
  EXPECT_TRUE(tips.normals.col(0).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  EXPECT_TRUE(tips.normals.col(2).isApprox(-Eigen::Vector3d::UnitZ(), 1e-12));
}

TEST(Kinematics, FlexingClosesFingersOneAndTwoOntoTheThumb) {
  // Knuckle at 0: fingers 1 and 2 oppose the thumb, so flexing brings
  // their tips towards the thumb's tip.
  Eigen::VectorXd q = Eigen::VectorXd::Zero(13);
  auto gap = [&](int finger) {
    const FingertipFrames t = fingertipFrames(m(), forwardKinematics(m(), q));
    return (t.positions.col(finger) - t.positions.col(2)).norm();
  };
  const double open1 = gap(0), open2 = gap(1);
  q.tail(6).setConstant(0.05);  // the tips start 3 cm apart: more would cross
  EXPECT_LT(gap(0), open1 - 0.005);
  EXPECT_LT(gap(1), open2 - 0.005);
  // Knuckle at 90 deg: fingers 1 and 2 face each other and close onto each other.
  q.setZero();
  q(6) = M_PI / 2;
  FingertipFrames turned = fingertipFrames(m(), forwardKinematics(m(), q));
  EXPECT_TRUE(turned.normals.col(0).isApprox(-turned.normals.col(1), 1e-12));
  EXPECT_GT(turned.normals.col(0).dot(turned.positions.col(1) - turned.positions.col(0)), 0.0);
  const double apart = (turned.positions.col(0) - turned.positions.col(1)).norm();
  q.segment(7, 4).setConstant(0.05);
  turned = fingertipFrames(m(), forwardKinematics(m(), q));
  EXPECT_LT((turned.positions.col(0) - turned.positions.col(1)).norm(), apart - 0.005);
}

TEST(Kinematics, JacobianMatchesFiniteDifferences) {
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd q(13);
    for (int d = 0; d < 13; ++d)
      q(d) =
          std::uniform_real_distribution<double>(m().lowerLimits()(d), m().upperLimits()(d))(rng);
    const Fingertip& tip = m().fingertips()[static_cast<std::size_t>(trial % 3)];
    const LinkPoses poses = forwardKinematics(m(), q);
    const auto j = jacobian(m(), poses, tip.link, tip.point);
    const double h = 1e-7;
    for (int d = 0; d < 13; ++d) {
      Eigen::VectorXd qp = q, qm = q;
      qp(d) += h;
      qm(d) -= h;
      const Eigen::Vector3d pp =
          forwardKinematics(m(), qp)[static_cast<std::size_t>(tip.link)] * tip.point;
      const Eigen::Vector3d pm =
          forwardKinematics(m(), qm)[static_cast<std::size_t>(tip.link)] * tip.point;
      EXPECT_TRUE(((pp - pm) / (2 * h)).isApprox(j.col(d).head<3>(), 1e-5) ||
                  ((pp - pm) / (2 * h) - j.col(d).head<3>()).norm() < 1e-8)
          << "dof " << d;
    }
  }
}

// Every fingertip point of every bundled robot, at configurations drawn
// within the limits and at the limits' corners, lies inside the reach ball;
// the stretched KR5 touches it nearly (the bound is the chain's length).
TEST(Kinematics, EveryFingertipStaysInsideTheReachBall) {
  for (const char* name : {"kr5_sdh", "panda_gripper", "ur5e_allegro"}) {
    SCOPED_TRACE(name);
    const RobotModel model =
        RobotModel::load(test::sourcePath(std::string("robots/") + name + "/" + name + ".json"));
    const ReachBall ball = fingertipReach(model);
    EXPECT_GT(ball.radius, 0.5);
    EXPECT_LT(ball.radius, 2.0);
    std::mt19937_64 rng(7);
    double farthest = 0.0;
    for (int trial = 0; trial < 20000; ++trial) {
      Eigen::VectorXd q(model.numDofs());
      for (Eigen::Index d = 0; d < q.size(); ++d)
        q(d) = trial % 2 == 0 ? std::uniform_real_distribution<double>(model.lowerLimits()(d),
                                                                       model.upperLimits()(d))(rng)
                              : (rng() % 2 == 0 ? model.lowerLimits()(d) : model.upperLimits()(d));
      const FingertipFrames tips = fingertipFrames(model, forwardKinematics(model, q));
      for (Eigen::Index t = 0; t < tips.positions.cols(); ++t) {
        const double r = (tips.positions.col(t) - ball.centre).norm();
        farthest = std::max(farthest, r);
        ASSERT_LE(r, ball.radius + 1e-12) << "fingertip " << t << " at trial " << trial;
      }
    }
    EXPECT_GT(farthest, 0.6 * ball.radius);
  }
  // The KR5's first axis is the base's z axis; straight along x the arm and
  // the hand nearly span the ball.
  const ReachBall kr5 = fingertipReach(m());
  EXPECT_NEAR(kr5.centre.x(), 0.0, 1e-12);
  EXPECT_NEAR(kr5.centre.y(), 0.0, 1e-12);
  const FingertipFrames stretched =
      fingertipFrames(m(), forwardKinematics(m(), Eigen::VectorXd::Zero(13)));
  EXPECT_GT((stretched.positions.col(0) - kr5.centre).norm(), 0.85 * kr5.radius);
}

}  // namespace
}  // namespace hfts::robot
