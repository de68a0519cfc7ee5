// Hand reachability for hands of two and four fingertips (the m-contact
// HFTS): a parallel-jaw gripper and a four-fingered hand, written here so
// that the tests do not depend on the bundled robots.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <string>

#include "grasp/hand_reachability.h"
#include "hand_fixture.h"
#include "robot/kinematics.h"
#include "test_meshes.h"

namespace hfts::grasp {
namespace {

/// A one-joint arm carrying a hand: the parts the hand tests need.
std::string armUrdf(const std::string& name, const std::string& hand) {
  return R"(<robot name=")" + name + R"(">
  <link name="base_link"/>
  <link name="flange"/>
  <joint name="a1" type="revolute">
    <parent link="base_link"/><child link="flange"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="1" effort="1"/>
  </joint>
  <link name="palm"><collision><origin xyz="0 0 0.03"/>
    <geometry><box size="0.08 0.12 0.06"/></geometry></collision></link>
  <joint name="mount" type="fixed"><parent link="flange"/><child link="palm"/></joint>
)" + hand +
         "</robot>";
}

/// A parallel-jaw gripper: two pads 0 to 8 cm apart, one DoF (mimic).
robot::RobotModel gripper() {
  const std::string hand = R"(
  <link name="left"><collision><origin xyz="0 0.005 0.025"/>
    <geometry><box size="0.02 0.01 0.05"/></geometry></collision></link>
  <joint name="left_joint" type="prismatic">
    <parent link="palm"/><child link="left"/><origin xyz="0 0 0.06"/>
    <axis xyz="0 1 0"/><limit lower="0" upper="0.04" velocity="0.2" effort="1"/>
  </joint>
  <link name="right"><collision><origin xyz="0 -0.005 0.025"/>
    <geometry><box size="0.02 0.01 0.05"/></geometry></collision></link>
  <joint name="right_joint" type="prismatic">
    <parent link="palm"/><child link="right"/><origin xyz="0 0 0.06"/>
    <axis xyz="0 -1 0"/><limit lower="0" upper="0.04" velocity="0.2" effort="1"/>
    <mimic joint="left_joint"/>
  </joint>
)";
  const std::string config = R"({
  "name": "test_gripper", "urdf": "-", "base_link": "base_link", "flange_link": "flange",
  "palm_link": "palm", "arm_joints": ["a1"], "hand_joints": ["left_joint"],
  "fingertips": [
    {"name": "left", "link": "left", "point": [0, 0, 0.045], "normal": [0, -1, 0]},
    {"name": "right", "link": "right", "point": [0, 0, 0.045], "normal": [0, 1, 0]}],
  "hand_open": [0.04], "pregrasp_offset": 0.01, "dof_weights": [1, 0.25],
  "home": [0, 0.04], "disabled_collisions": [["palm", "left"], ["palm", "right"]]})";
  return robot::RobotModel::fromStrings(armUrdf("test_gripper", hand), config, "test gripper");
}

/// One finger of the four-fingered hand: two flexing joints, the pad on
/// the distal link's -x side.
std::string finger(const std::string& name, const std::string& xyz, const std::string& rpy) {
  return R"(
  <link name=")" +
         name + R"(_proximal"><collision><origin xyz="0 0 0.025"/>
    <geometry><cylinder radius="0.008" length="0.05"/></geometry></collision></link>
  <joint name=")" +
         name + R"(_1" type="revolute">
    <parent link="palm"/><child link=")" +
         name + R"(_proximal"/>
    <origin xyz=")" +
         xyz + R"(" rpy=")" + rpy + R"("/>
    <axis xyz="0 -1 0"/><limit lower="-0.4" upper="1.4" velocity="1" effort="1"/>
  </joint>
  <link name=")" +
         name + R"(_distal"><collision><origin xyz="0 0 0.02"/>
    <geometry><cylinder radius="0.008" length="0.04"/></geometry></collision></link>
  <joint name=")" +
         name + R"(_2" type="revolute">
    <parent link=")" +
         name + R"(_proximal"/><child link=")" + name + R"(_distal"/>
    <origin xyz="0 0 0.05"/>
    <axis xyz="0 -1 0"/><limit lower="0" upper="1.4" velocity="1" effort="1"/>
  </joint>
)";
}

/// Three fingers side by side facing a thumb: eight DoF, four fingertips.
robot::RobotModel fourFingers() {
  const std::string hand = finger("index", "0.03 0.03 0.06", "0 0 0") +
                           finger("middle", "0.03 0 0.06", "0 0 0") +
                           finger("ring", "0.03 -0.03 0.06", "0 0 0") +
                           finger("thumb", "-0.03 0 0.06", "0 0 3.141592653589793");
  std::string tips, joints, pairs;
  for (const std::string name : {"index", "middle", "ring", "thumb"}) {
    tips += std::string(tips.empty() ? "" : ",") + R"({"name": ")" + name + R"(", "link": ")" +
            name + R"(_distal", "point": [-0.008, 0, 0.03], "normal": [-1, 0, 0]})";
    joints += std::string(joints.empty() ? "" : ",") + "\"" + name + "_1\", \"" + name + "_2\"";
    pairs += R"(, ["palm", ")" + name + R"(_proximal"], [")" + name + R"(_proximal", ")" + name +
             R"(_distal"])";
  }
  const std::string config = R"({
  "name": "test_four_fingers", "urdf": "-", "base_link": "base_link", "flange_link": "flange",
  "palm_link": "palm", "arm_joints": ["a1"], "hand_joints": [)" +
                             joints + R"(], "fingertips": [)" + tips + R"(],
  "hand_open": [0, 0, 0, 0, 0, 0, 0, 0], "pregrasp_offset": 0.02,
  "dof_weights": [1, 0.25, 0.25, 0.25, 0.25, 0.25, 0.25, 0.25, 0.25],
  "home": [0, 0, 0, 0, 0, 0, 0, 0, 0], "disabled_collisions": [)" +
                             pairs.substr(2) + "]}";
  return robot::RobotModel::fromStrings(armUrdf("test_four_fingers", hand), config,
                                        "test four fingers");
}

/// A hand with its map (smaller than the default: these tests only need
/// samples to start from) and the default query.
struct Hand {
  robot::RobotModel model;
  db::HandMap map;
  HandReachability reachability;

  explicit Hand(robot::RobotModel m)
      : model(std::move(m)), map(buildHandMap(model, smallMap())), reachability(model, map) {}

  static HandMapOptions smallMap() {
    HandMapOptions options;
    options.num_samples = 2000;
    return options;
  }
};

const Hand& hand(int fingers) {
  static const Hand two(gripper());
  static const Hand four(fourFingers());
  return fingers == 2 ? two : four;
}

using Posture = test::HandPosture;
using test::randomGraspPosture;
using test::randomPose;

Posture postureOf(const robot::RobotModel& model, const Eigen::VectorXd& hand) {
  return test::handPostureOf(model, hand);
}

/// Contacts the hand reaches exactly: fingertips moved rigidly, outward
/// normals against the pads, in shuffled order (order[c]: the finger that
/// made contact c).
struct Contacts {
  Eigen::Matrix3Xd positions;
  Eigen::Matrix3Xd outward;
  std::vector<int> order;
};

Contacts reachable(const Posture& p, const Eigen::Isometry3d& pose, std::mt19937_64& rng) {
  const auto m = p.tips.cols();
  Contacts c{Eigen::Matrix3Xd(3, m), Eigen::Matrix3Xd(3, m), std::vector<int>(m)};
  std::iota(c.order.begin(), c.order.end(), 0);
  std::shuffle(c.order.begin(), c.order.end(), rng);
  for (Eigen::Index i = 0; i < m; ++i) {
    c.positions.col(i) = pose * Eigen::Vector3d(p.tips.col(c.order[static_cast<std::size_t>(i)]));
    c.outward.col(i) = -(pose.linear() * p.pads.col(c.order[static_cast<std::size_t>(i)]));
  }
  return c;
}

/// The answer, checked by the model's forward kinematics: a permutation of
/// the fingers, a grasp posture within the limits, a palm pose that is a
/// rigid motion, and the fingertips where the reported residual says they
/// are.
void expectConsistent(const Hand& h, const HandQuery& answer, const Contacts& c) {
  const auto m = static_cast<std::size_t>(c.positions.cols());
  const Eigen::Matrix3d r = answer.palm_pose.linear();
  EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 1e-9);
  EXPECT_NEAR(r.determinant(), 1.0, 1e-9);
  ASSERT_EQ(answer.finger_of_contact.size(), m);
  std::vector<int> fingers = answer.finger_of_contact;
  std::sort(fingers.begin(), fingers.end());
  std::vector<int> all(m);
  std::iota(all.begin(), all.end(), 0);
  EXPECT_EQ(fingers, all);
  Eigen::VectorXd q = h.model.home();
  q.tail(h.model.numHandDofs()) = answer.hand_configuration;
  EXPECT_TRUE(h.model.withinLimits(q));
  const Posture p = postureOf(h.model, answer.hand_configuration);
  EXPECT_TRUE(isGraspPosture(p.tips, p.pads, h.map.parameters));
  const double lambda = h.map.parameters.normal_weight;
  double sum = 0;
  for (std::size_t i = 0; i < m; ++i) {
    const int f = answer.finger_of_contact[i];
    const auto col = static_cast<Eigen::Index>(i);
    const Eigen::Vector3d tip = answer.palm_pose * Eigen::Vector3d(p.tips.col(f));
    const Eigen::Vector3d pad = answer.palm_pose.linear() * p.pads.col(f);
    sum += (tip - c.positions.col(col)).squaredNorm() +
           lambda * lambda * (pad + c.outward.col(col)).squaredNorm();
  }
  EXPECT_NEAR(std::sqrt(sum / static_cast<double>(m)), answer.residual, 1e-9);
}

class FingerCount : public ::testing::TestWithParam<int> {};

INSTANTIATE_TEST_SUITE_P(Hands, FingerCount, ::testing::Values(2, 4),
                         [](const ::testing::TestParamInfo<int>& hands) {
                           return std::to_string(hands.param) + "Fingers";
                         });

TEST_P(FingerCount, MapHasOneColumnTripletPerFingerAndItsDescriptor) {
  const Hand& h = hand(GetParam());
  const int m = GetParam();
  EXPECT_EQ(h.map.numFingers(), static_cast<std::size_t>(m));
  EXPECT_EQ(h.map.positions.cols(), 3 * m);
  EXPECT_EQ(h.map.normals.cols(), 3 * m);
  EXPECT_EQ(h.map.descriptor, handDescriptorName(m));
  EXPECT_EQ(h.map.descriptors.cols(), handDescriptorSize(m));
  EXPECT_EQ(h.map.numSamples(), 2000u);
  for (Eigen::Index s = 0; s < h.map.configurations.rows(); s += 97) {
    const Posture p = postureOf(h.model, h.map.configurations.row(s).transpose());
    const Eigen::Map<const Eigen::Matrix3Xd> tips(h.map.positions.row(s).data(), 3, m);
    const Eigen::Map<const Eigen::Matrix3Xd> pads(h.map.normals.row(s).data(), 3, m);
    ASSERT_LT((tips - p.tips).norm(), 1e-12) << s;
    ASSERT_LT((pads - p.pads).norm(), 1e-12) << s;
    ASSERT_TRUE(isGraspPosture(tips, pads, h.map.parameters)) << s;
  }
}

TEST_P(FingerCount, DescriptorInvariantUnderRigidMotionNotUnderMirroring) {
  const Hand& h = hand(GetParam());
  std::mt19937_64 rng(3);
  for (int i = 0; i < 20; ++i) {
    const Posture p = randomGraspPosture(h.model, rng);
    const Eigen::Isometry3d pose = randomPose(rng);
    const HandDescriptor d = handDescriptor(p.tips, p.pads, 0.03);
    ASSERT_EQ(d.size(), handDescriptorSize(GetParam()));
    const Eigen::Matrix3Xd moved = pose * p.tips;
    EXPECT_LT((handDescriptor(moved, pose.linear() * p.pads, 0.03) - d).norm(), 1e-12);
    // Tilt the pads so that the grasp has a handedness, then mirror it.
    Eigen::Matrix3Xd tilted = p.pads;
    for (Eigen::Index f = 0; f < tilted.cols(); ++f)
      tilted.col(f) = (tilted.col(f) + 0.3 * Eigen::Vector3d(0.2 * f, 1, 0.5)).normalized();
    const Eigen::Matrix3d mirror = Eigen::Vector3d(1, 1, -1).asDiagonal();
    EXPECT_GT((handDescriptor(mirror * p.tips, mirror * tilted, 0.03) -
               handDescriptor(p.tips, tilted, 0.03))
                  .norm(),
              1e-4);
  }
}

TEST_P(FingerCount, ZeroForTheFingertipsOfRandomGraspPostures) {
  const Hand& h = hand(GetParam());
  const HandReachability thorough(h.model, h.map, HandQueryOptions::thorough());
  std::mt19937_64 rng(7);
  int reached = 0;
  const int n = 60;
  for (int i = 0; i < n; ++i) {
    const Contacts c = reachable(randomGraspPosture(h.model, rng), randomPose(rng), rng);
    const HandQuery answer = thorough.query(c.positions, c.outward);
    SCOPED_TRACE(i);
    expectConsistent(h, answer, c);
    reached += answer.residual < 1e-4 ? 1 : 0;
  }
  EXPECT_GE(reached, n * 9 / 10);
}

TEST_P(FingerCount, ExactForMapSamplesInAnyContactOrder) {
  const Hand& h = hand(GetParam());
  const int m = GetParam();
  std::mt19937_64 rng(5);
  for (int i = 0; i < 40; ++i) {
    const auto s = static_cast<Eigen::Index>(rng() % h.map.numSamples());
    const Posture p{h.map.configurations.row(s).transpose(),
                    Eigen::Map<const Eigen::Matrix3Xd>(h.map.positions.row(s).data(), 3, m),
                    Eigen::Map<const Eigen::Matrix3Xd>(h.map.normals.row(s).data(), 3, m)};
    const Contacts c = reachable(p, randomPose(rng), rng);
    const HandQuery answer = h.reachability.query(c.positions, c.outward);
    SCOPED_TRACE(i);
    EXPECT_LT(answer.residual, 1e-6);
    expectConsistent(h, answer, c);
  }
}

TEST_P(FingerCount, LargeForContactsTheHandCannotSpan) {
  const Hand& h = hand(GetParam());
  const int m = GetParam();
  // Contacts 40 cm apart on a circle, normals pointing out: beyond any
  // fingertip of these hands.
  Eigen::Matrix3Xd positions(3, m), outward(3, m);
  for (int c = 0; c < m; ++c) {
    const double a = 2 * M_PI * c / m;
    outward.col(c) = Eigen::Vector3d(std::cos(a), std::sin(a), 0);
    positions.col(c) = 0.2 * outward.col(c);
  }
  const HandQuery answer = h.reachability.query(positions, outward);
  EXPECT_GT(answer.position_error, 0.05);
  test::expectErrorMentioning<std::invalid_argument>(
      [&] { h.reachability.query(positions.leftCols(m - 1), outward.leftCols(m - 1)); },
      {"contactPositions", "3 x " + std::to_string(m)});
}

/// R(h) recomputed by forward kinematics for the answer's posture with the
/// palm at `palm`.
double residualAt(const Hand& h, const HandQuery& answer, const Contacts& c,
                  const Eigen::Isometry3d& palm) {
  const Posture p = postureOf(h.model, answer.hand_configuration);
  const double lambda = h.map.parameters.normal_weight;
  double sum = 0;
  for (Eigen::Index i = 0; i < c.positions.cols(); ++i) {
    const int f = answer.finger_of_contact[static_cast<std::size_t>(i)];
    sum += (palm * Eigen::Vector3d(p.tips.col(f)) - c.positions.col(i)).squaredNorm() +
           lambda * lambda * (palm.linear() * p.pads.col(f) + c.outward.col(i)).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(c.positions.cols()));
}

TEST(FreeTurn, AGripperTurnsAboutItsJawLineWithoutChangingTheResidual) {
  const Hand& h = hand(2);
  std::mt19937_64 rng(11);
  for (int i = 0; i < 20; ++i) {
    const Contacts c = reachable(randomGraspPosture(h.model, rng), randomPose(rng), rng);
    const HandQuery answer = h.reachability.query(c.positions, c.outward);
    SCOPED_TRACE(i);
    ASSERT_TRUE(answer.free_turn.has_value());
    // The line runs through both contacts (within the residual).
    const Eigen::Vector3d u = (c.positions.col(1) - c.positions.col(0)).normalized();
    EXPECT_NEAR(std::abs(answer.free_turn->direction().dot(u)), 1.0, 1e-6);
    EXPECT_LT(answer.free_turn->distance(c.positions.col(0)), 1e-4);
    EXPECT_EQ(turnedPalm(answer, 0.0).matrix(), answer.palm_pose.matrix());
    for (const double angle : {0.5, M_PI / 2, 2.0, M_PI, -1.0}) {
      const Eigen::Isometry3d turned = turnedPalm(answer, angle);
      EXPECT_NEAR(residualAt(h, answer, c, turned), answer.residual, 1e-9) << angle;
      // A real turn: the palm's approach axis moves by the angle.
      const double moved = std::acos(
          std::clamp(turned.linear().col(2).dot(answer.palm_pose.linear().col(2)), -1.0, 1.0));
      EXPECT_NEAR(moved, std::abs(std::remainder(angle, 2 * M_PI)), 1e-6) << angle;
    }
  }
}

TEST(FreeTurn, AFourFingeredHandHasNone) {
  const Hand& h = hand(4);
  std::mt19937_64 rng(12);
  const Contacts c = reachable(randomGraspPosture(h.model, rng), randomPose(rng), rng);
  const HandQuery answer = h.reachability.query(c.positions, c.outward);
  EXPECT_FALSE(answer.free_turn.has_value());
  EXPECT_EQ(turnedPalm(answer, 1.0).matrix(), answer.palm_pose.matrix());
}

TEST(IsGraspPosture, TwoOpposingPadsSqueezeWithinTheFrictionCone) {
  const HandMapOptions options;  // friction 0.5: cones of 26.6 deg
  Eigen::Matrix3Xd tips(3, 2), pads(3, 2);
  tips << 0, 0, 0.03, -0.03, 0, 0;
  pads << 0, 0, -1, 1, 0, 0;
  EXPECT_TRUE(isGraspPosture(tips, pads, options));
  EXPECT_FALSE(isGraspPosture(tips, -pads, options));
  // One pad tilted by 0.4 rad: the segment between the normals passes
  // sin(0.2) = 0.2 < 0.447 from the origin; by 1.2 rad: 0.56 > 0.447.
  pads.col(1) = Eigen::Vector3d(0, std::cos(0.4), std::sin(0.4));
  EXPECT_TRUE(isGraspPosture(tips, pads, options));
  pads.col(1) = Eigen::Vector3d(0, std::cos(1.2), std::sin(1.2));
  EXPECT_FALSE(isGraspPosture(tips, pads, options));
}

TEST(IsGraspPosture, FourPadsNeedTheOriginNearTheirTetrahedron) {
  const HandMapOptions options;
  Eigen::Matrix3Xd tips(3, 4), pads(3, 4);
  // Three fingers at x = +3 cm facing a thumb at x = -3 cm.
  tips << 0.03, 0.03, 0.03, -0.03, 0.03, 0, -0.03, 0, 0, 0, 0, 0;
  pads << -1, -1, -1, 1, 0, 0, 0, 0, 0, 0, 0, 0;
  EXPECT_TRUE(isGraspPosture(tips, pads, options));
  // All four pads pushing into +z and -x: no squeeze.
  Eigen::Matrix3Xd same(3, 4);
  for (int f = 0; f < 4; ++f) same.col(f) = Eigen::Vector3d(-0.6, 0, 0.8);
  EXPECT_FALSE(isGraspPosture(tips, same, options));
  // A regular tetrahedron of normals holds the origin inside.
  Eigen::Matrix3Xd spread(3, 4);
  spread << 1, -1, -1, 1, 1, -1, 1, -1, 1, 1, -1, -1;
  spread /= std::sqrt(3.0);
  Eigen::Matrix3Xd around(3, 4);
  around << 0.03, -0.03, -0.03, 0.03, 0.03, -0.03, 0.03, -0.03, 0.03, 0.03, -0.03, -0.03;
  // Pads pushing towards the centre: the negated corners.
  EXPECT_TRUE(isGraspPosture(around, -spread, options));
  // Two fingertips 5 mm apart are not a grasp.
  Eigen::Matrix3Xd close = tips;
  close.col(1) = close.col(0) + Eigen::Vector3d(0, 0.005, 0);
  EXPECT_FALSE(isGraspPosture(close, pads, options));
}

TEST(HandMapBuilder, RejectsHandsOfOneOrFiveFingertips) {
  test::expectErrorMentioning<std::invalid_argument>([] { handDescriptorSize(5); },
                                                     {"fingers", "2..4"});
  test::expectErrorMentioning<std::invalid_argument>([] { handDescriptorName(1); }, {"fingers"});
}

}  // namespace
}  // namespace hfts::grasp
