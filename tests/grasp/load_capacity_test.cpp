#include "grasp/load_capacity.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/invalid_argument.h"
#include "panda_cube.h"
#include "robot/kinematics.h"

namespace hfts::grasp {
namespace {

constexpr double kMu = 0.5;

/// Two pads squeeze a body from +-x; each is driven by its own DoF, whose
/// force (or torque at `lever`) pushes its pad along its inward normal.
LoadCapacityRequest squeeze(double effort, double lever, double weight) {
  LoadCapacityRequest r;
  r.positions.resize(3, 2);
  r.positions << 0.02, -0.02, 0, 0, 0, 0;
  r.normals.resize(3, 2);
  r.normals << -1, 1, 0, 0, 0, 0;
  for (int i = 0; i < 2; ++i) {
    Eigen::MatrixXd j = Eigen::MatrixXd::Zero(6, 2);
    j.block<3, 1>(0, i) = lever * r.normals.col(i);  // the DoF moves its pad inwards
    r.jacobians.push_back(j);
  }
  r.efforts = Eigen::Vector2d::Constant(effort);
  r.weight = weight;
  r.friction = kMu;
  return r;
}

TEST(LoadCapacity, TwoPadsHoldWhatTheirFrictionCarries) {
  // 10 N per pad: friction carries 2 mu 10 = 10 N of weight; the -z
  // disturbance doubles the load, so the grasp holds 5 N of weight.
  // The pyramid is around the cone: mu at most 1 / cos(pi / K) larger.
  const LoadCapacity c = loadCapacity(squeeze(10.0, 1.0, 1.0));
  const double outer = kMu / std::cos(M_PI / 8.0);
  EXPECT_GE(c.per_case[0], 2.0 * kMu * 10.0 - 1e-6);
  EXPECT_LE(c.per_case[0], 2.0 * outer * 10.0 + 1e-6);
  EXPECT_EQ(c.per_case[5], kUnboundedLoad);  // +z cancels the weight
  EXPECT_NEAR(c.per_case[6], c.per_case[0] / 2.0, 1e-6);
  EXPECT_EQ(c.factor, *std::min_element(c.per_case.begin(), c.per_case.end()));
  // Along the pads' axis (+x) the pad at -x pushes less: F2 = F - lambda W.
  // The torque about the centre splits the weight evenly between the two
  // pads, so lambda W / 2 <= mu (F - lambda W): lambda = mu F / (1/2 + mu).
  EXPECT_GE(c.per_case[1], kMu * 10.0 / (0.5 + kMu) - 1e-6);
  EXPECT_LE(c.per_case[1], outer * 10.0 / (0.5 + outer) + 1e-6);
}

TEST(LoadCapacity, AFingerDrivenThroughALeverPushesItsTorqueOverTheLever) {
  // 1 N m at 0.1 m is 10 N, as above.
  const LoadCapacity direct = loadCapacity(squeeze(10.0, 1.0, 1.0));
  const LoadCapacity lever = loadCapacity(squeeze(1.0, 0.1, 1.0));
  EXPECT_NEAR(lever.factor, direct.factor, 1e-6);
  // Ten times the weight: a tenth of the factor.
  EXPECT_NEAR(loadCapacity(squeeze(10.0, 1.0, 10.0)).factor, direct.factor / 10.0, 1e-6);
}

TEST(LoadCapacity, AGraspWithoutFrictionHoldsNoWeight) {
  LoadCapacityRequest r = squeeze(10.0, 1.0, 1.0);
  r.friction = 1e-9;
  EXPECT_LT(loadCapacity(r).factor, 1e-6);
}

TEST(LoadCapacity, TheFrankaHandSqueezesTheCubeWithItsRatedForce) {
  const test::PandaCube world;
  const robot::RobotModel& panda = test::panda();
  // The jaws at the cube's faces (the world's +-y), where the pads touch.
  const robot::LinkPoses poses = robot::forwardKinematics(panda, world.grasp);
  const robot::FingertipFrames tips = robot::fingertipFrames(panda, poses);
  HandClosure closure;
  closure.hand = world.grasp.tail(panda.numHandDofs());
  const Eigen::Isometry3d toObject = world.scene.target_pose.inverse() * world.scene.robot_base;
  for (Eigen::Index i = 0; i < tips.positions.cols(); ++i) {
    FingerClosure f;
    f.stop = FingerStop::kPadContact;
    f.contact = toObject * tips.positions.col(i);
    f.outward_normal = toObject.linear() * tips.normals.col(i);  // the pad faces the cube
    closure.fingers.push_back(f);
  }
  const double mass = 0.1;
  const LoadCapacityRequest r =
      loadRequest(panda, world.grasp, world.scene.robot_base, closure, world.scene.target_pose,
                  test::smallCube().geometry.center_of_mass, mass);
  ASSERT_EQ(r.jacobians.size(), 2u);
  // 70 N on the one DoF is 35 N per jaw; with the -z disturbance the
  // friction of two pads carries 2 mu 35 N = 35 N of twice the weight.
  const double weight = mass * 9.81;
  const LoadCapacity c = loadCapacity(r);
  EXPECT_GE(c.factor, 35.0 / (2.0 * weight) - 1e-6);
  EXPECT_LE(c.factor, 35.0 / std::cos(M_PI / 8.0) / (2.0 * weight) + 1e-6);
  // Too heavy for the hand: 5 kg.
  const LoadCapacity heavy = loadCapacity(
      loadRequest(panda, world.grasp, world.scene.robot_base, closure, world.scene.target_pose,
                  test::smallCube().geometry.center_of_mass, 5.0));
  EXPECT_LT(heavy.factor, 1.0);
}

TEST(LoadCapacity, BadRequestsNameTheirField) {
  LoadCapacityRequest r = squeeze(10.0, 1.0, 1.0);
  r.weight = 0.0;
  test::expectErrorMentioning<InvalidArgument>([&] { loadCapacity(r); }, {"weight"});
  r = squeeze(10.0, 1.0, 1.0);
  r.jacobians.pop_back();
  test::expectErrorMentioning<InvalidArgument>([&] { loadCapacity(r); }, {"jacobians"});
  r = squeeze(10.0, 1.0, 1.0);
  r.efforts(1) = -1.0;
  test::expectErrorMentioning<InvalidArgument>([&] { loadCapacity(r); }, {"efforts"});
}

}  // namespace
}  // namespace hfts::grasp
