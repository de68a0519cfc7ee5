#include "grasp/hand_closing.h"

#include <gtest/gtest.h>

#include <random>

#include "bundled_objects.h"
#include "core/invalid_argument.h"
#include "grasp/grasp_configurations.h"
#include "grasp/hand_reachability.h"
#include "hand_fixture.h"
#include "robot/kinematics.h"
#include "robot/link_spheres.h"
#include "robot_fixture.h"
#include "test_meshes.h"

namespace hfts::grasp {
namespace {

const robot::RobotModel& panda() {
  static const robot::RobotModel model =
      robot::RobotModel::load(test::sourcePath("robots/panda_gripper/panda_gripper.json"));
  return model;
}

/// A cube of side `size` centred at `center` (object frame = its mesh's).
db::ObjectGeometry cube(double size, const Eigen::Vector3d& center = Eigen::Vector3d::Zero()) {
  return test::meshObject(test::cube(size, center));
}

/// The Panda's palm pose (object frame) that puts the midpoint between its
/// fingertip points at the origin, jaws along the object's y axis.
Eigen::Isometry3d palmAroundOrigin() {
  Eigen::VectorXd q = panda().home();
  q.tail(1) << 0.04;
  const robot::LinkPoses poses = robot::forwardKinematics(panda(), q);
  const robot::FingertipFrames tips = robot::fingertipFrames(panda(), poses);
  const Eigen::Isometry3d palm = poses[static_cast<std::size_t>(panda().palmLink())];
  const Eigen::Vector3d middle = (tips.positions.col(0) + tips.positions.col(1)) / 2;
  return Eigen::Translation3d(-(palm.inverse() * middle)) * Eigen::Isometry3d::Identity();
}

/// Signed distance from fingertip f's link to `point` (object frame) at
/// the closure's posture and palm: 0 when the point is on the link.
double linkToPoint(const HandClosure& closure, std::size_t f, const Eigen::Vector3d& point) {
  Eigen::VectorXd q = panda().home();
  q.tail(1) = closure.hand;
  const robot::LinkPoses poses = robot::forwardKinematics(panda(), q);
  const int link = panda().fingertips()[f].link;
  const Eigen::Isometry3d toObject =
      closure.palm * poses[static_cast<std::size_t>(panda().palmLink())].inverse();
  return robot::signedDistance(
      panda().links()[static_cast<std::size_t>(link)],
      (toObject * poses[static_cast<std::size_t>(link)]).inverse() * point);
}

TEST(HandCloser, APadShortOfTheSurfaceClosesOnToContact) {
  // A 5 cm cube between jaws opened to 8 cm; the planned grasp leaves each
  // pad 5 mm short of its face (jaws at 3 cm): the closing goes on past it.
  const db::ObjectGeometry box = cube(0.05);
  const robot::ObjectSurface surface(box);
  const HandCloser closer(test::collisionOf(panda()), surface);
  const HandClosure closed = closer.close(palmAroundOrigin(), Eigen::VectorXd::Constant(1, 0.04),
                                          Eigen::VectorXd::Constant(1, 0.03));
  ASSERT_TRUE(closed.touches()) << closed.failure(panda());
  EXPECT_EQ(closed.failure(panda()), "");
  EXPECT_NEAR(closed.hand(0), 0.025, ClosingOptions{}.contact_distance);
  EXPECT_GE(closed.hand(0), 0.025);  // never into the cube
  for (std::size_t f = 0; f < 2; ++f) {
    const FingerClosure& finger = closed.fingers[f];
    EXPECT_EQ(finger.stop, FingerStop::kPadContact);
    EXPECT_NEAR(finger.travel, 1.5, 0.02);
    EXPECT_NEAR(std::abs(finger.contact.y()), 0.025, 1e-9) << "on a jaw's face";
    EXPECT_NEAR(std::abs(finger.outward_normal.y()), 1.0, 1e-9);
    EXPECT_LE(linkToPoint(closed, f, finger.contact), ClosingOptions{}.contact_distance + 1e-9);
  }
  // The contacts oppose each other: a pinch.
  const GraspContacts c = closed.contacts();
  EXPECT_LT(c.outward_normals.col(0).dot(c.outward_normals.col(1)), -0.999);
  EXPECT_TRUE(closed.palm.isApprox(palmAroundOrigin(), 1e-12)) << "centred already";
}

TEST(HandCloser, AFingerTheClosingDoesNotMoveTouchesWhereItIsWithinTheContactDistance) {
  // The planned posture is the open one: nothing moves. Jaws 0.05 mm off
  // the 5 cm cube's faces touch them; 0.3 mm off, they do not. (A still
  // finger 0.05 mm off once counted as stopped by its joint limit, and one
  // just on the face as touching, so a plan's re-check from its pre-grasp
  // could turn on the last digits of the palm.)
  const db::ObjectGeometry box = cube(0.05);
  const robot::ObjectSurface surface(box);
  const HandCloser closer(test::collisionOf(panda()), surface);
  for (const double jaw : {0.02505, 0.0253}) {
    SCOPED_TRACE(jaw);
    const Eigen::VectorXd still = Eigen::VectorXd::Constant(1, jaw);
    const HandClosure closed = closer.close(palmAroundOrigin(), still, still);
    EXPECT_EQ(closed.hand(0), jaw);
    for (const FingerClosure& finger : closed.fingers)
      EXPECT_EQ(finger.stop, jaw < 0.0252 ? FingerStop::kPadContact : FingerStop::kJointLimit);
  }
}

TEST(HandCloser, AGrippersPalmMovesSoThatBothJawsTouch) {
  // The cube 3 mm towards the left jaw (+y): that jaw would touch first and
  // leave the right one 6 mm off; a gripper centres the object between its
  // jaws, the planner centres the palm on the object instead.
  const db::ObjectGeometry box = cube(0.05, {0.0, 0.003, 0.0});
  const robot::ObjectSurface surface(box);
  const HandClosure closed = HandCloser(test::collisionOf(panda()), surface)
                                 .close(palmAroundOrigin(), Eigen::VectorXd::Constant(1, 0.04),
                                        Eigen::VectorXd::Constant(1, 0.03));
  ASSERT_TRUE(closed.touches()) << closed.failure(panda());
  const Eigen::Vector3d moved = closed.palm.translation() - palmAroundOrigin().translation();
  EXPECT_NEAR(moved.y(), 0.003, 2e-4) << moved.transpose();
  EXPECT_NEAR(moved.x(), 0.0, 1e-9);
  EXPECT_NEAR(moved.z(), 0.0, 1e-9);
  EXPECT_NEAR(closed.hand(0), 0.025, 2e-4);

  // Without room to centre (one jaw held back by nothing it can reach: the
  // object beyond the other's stroke), the other jaw stops at its limit.
  const db::ObjectGeometry far = cube(0.02, {0.0, 0.0, 0.5});
  const robot::ObjectSurface nowhere(far);
  const HandClosure empty = HandCloser(test::collisionOf(panda()), nowhere)
                                .close(palmAroundOrigin(), Eigen::VectorXd::Constant(1, 0.04),
                                       Eigen::VectorXd::Constant(1, 0.03));
  EXPECT_FALSE(empty.touches());
  for (const FingerClosure& f : empty.fingers) EXPECT_EQ(f.stop, FingerStop::kJointLimit);
  EXPECT_DOUBLE_EQ(empty.hand(0), 0.0);  // closed to the limit
  EXPECT_NE(empty.failure(panda()).find("joint limit"), std::string::npos);
}

TEST(HandCloser, AFingerThatMeetsTheObjectWithAnotherPartIsNotAPadContact) {
  // Opening the jaws from 2 to 4 cm drives the left jaw's back (its outer
  // face, 16 mm behind the pad) into a block beside it: another part of
  // the finger than its pad, which stops it.
  const db::ObjectGeometry block = cube(0.01, {0.0, 0.045, 0.0});
  const robot::ObjectSurface surface(block);
  const HandClosure closed = HandCloser(test::collisionOf(panda()), surface)
                                 .close(palmAroundOrigin(), Eigen::VectorXd::Constant(1, 0.02),
                                        Eigen::VectorXd::Constant(1, 0.04));
  ASSERT_EQ(closed.fingers.size(), 2u);
  EXPECT_EQ(closed.fingers[0].stop, FingerStop::kOtherContact) << toString(closed.fingers[0].stop);
  EXPECT_EQ(closed.fingers[0].link, "panda_leftfinger");
  EXPECT_EQ(closed.fingers[1].stop, FingerStop::kCoupled);
  EXPECT_NEAR(closed.hand(0), 0.024, ClosingOptions{}.contact_distance);
  EXPECT_FALSE(closed.touches());
  EXPECT_NE(closed.failure(panda()).find("another part"), std::string::npos)
      << closed.failure(panda());
}

TEST(HandCloser, AFingerThatStartsDeeperThanATouchInsideTheObjectIsInside) {
  // Jaws opened to 4 cm on a 5 cm cube: each pad starts 5 mm inside it.
  const db::ObjectGeometry box = cube(0.05);
  const robot::ObjectSurface surface(box);
  const HandCloser closer(test::collisionOf(panda()), surface);
  const HandClosure deep = closer.close(palmAroundOrigin(), Eigen::VectorXd::Constant(1, 0.02),
                                        Eigen::VectorXd::Constant(1, 0.015));
  EXPECT_FALSE(deep.touches());
  EXPECT_EQ(deep.fingers[0].stop, FingerStop::kInside) << toString(deep.fingers[0].stop);
  // Starting within a touch of the faces is a touch already.
  const HandClosure touching =
      closer.close(palmAroundOrigin(), Eigen::VectorXd::Constant(1, 0.02505),
                   Eigen::VectorXd::Constant(1, 0.02));
  ASSERT_TRUE(touching.touches()) << touching.failure(panda());
  EXPECT_NEAR(touching.hand(0), 0.02505, 1e-9);
}

TEST(HandCloser, APadFlatOnAFaceOffItsPointTouchesAtThePatchCentreWhateverTheLastDigit) {
  // A 6 mm cube beside the fingertip points (4 mm along x): each jaw's pad
  // lies flat on a face that does not reach its point. FCL's nearest
  // points are any of the face; the contact is the face's centre, and a
  // palm moved by 1e-12 m closes on the same contacts.
  const db::ObjectGeometry box = cube(0.006, {0.004, 0.0, 0.0});
  const robot::ObjectSurface surface(box);
  const HandCloser closer(test::collisionOf(panda()), surface);
  // The centre to within the patch grid's step (1.5 pad radii / 8, 1.5 mm
  // on the Panda's 8 mm pad).
  std::vector<Eigen::Vector3d> first;
  for (const double nudge : {0.0, 1e-12, -1e-12}) {
    SCOPED_TRACE(nudge);
    const Eigen::Isometry3d palm = Eigen::Translation3d(nudge, nudge, 0.0) * palmAroundOrigin();
    const HandClosure closed =
        closer.close(palm, Eigen::VectorXd::Constant(1, 0.04), Eigen::VectorXd::Constant(1, 0.03));
    ASSERT_TRUE(closed.touches()) << closed.failure(panda());
    for (std::size_t f = 0; f < 2; ++f) {
      const Eigen::Vector3d& c = closed.fingers[f].contact;
      EXPECT_NEAR(c.x(), 0.004, 1e-3) << c.transpose();
      EXPECT_NEAR(std::abs(c.y()), 0.003, 1e-9);
      EXPECT_NEAR(c.z(), 0.0, 1e-3) << c.transpose();
      if (first.size() < 2)
        first.push_back(c);
      else
        EXPECT_LT((c - first[f]).norm(), 1e-9) << "moved with the last digit";
    }
  }
  // Both jaws' contacts on one line across the cube: a pinch through it.
  ASSERT_EQ(first.size(), 2u);
  EXPECT_NEAR(first[0].x(), first[1].x(), 1e-9);
  EXPECT_NEAR(first[0].z(), first[1].z(), 1e-9);
}

TEST(HandCloser, TheSdhClosesOnTheMugWithEveryPadOnTheSurface) {
  // Leaf grasps of the mug as the thorough hand map answers them: where
  // every pad touches, each fingertip link is within the contact distance
  // of its contact, and no closing passed through the mug.
  const robot::RobotModel& sdh = test::kr5Sdh();
  const db::ObjectDatabase mug = test::bundledObject(test::bundledMeshDir() / "mug.ply");
  const robot::ObjectSurface surface(mug.geometry);
  const HandCloser closer(test::collisionOf(sdh), surface);
  const HftsSpace space(mug, 3);
  const HandReachability& hand = test::kr5SdhReachability();
  std::mt19937_64 rng(7);
  int touching = 0;
  for (int k = 0; k < 400 && touching < 5; ++k) {
    HftsNode node = space.root();
    while (!space.isLeaf(node))
      node = space.child(
          node, std::uniform_int_distribution<std::uint64_t>(0, space.numChildren(node) - 1)(rng));
    const GraspContacts planned = space.representative(node);
    const HandQuery h = hand.query(planned.positions, planned.outward_normals);
    if (h.position_error > 0.008) continue;  // what the planner would not close
    Eigen::VectorXd q = sdh.home();
    q.tail(sdh.numHandDofs()) = h.hand_configuration;
    const HandClosure closed =
        closer.close(h.palm_pose, openedHand(sdh, h.hand_configuration), h.hand_configuration);
    if (!closed.touches()) continue;
    ++touching;
    q.tail(sdh.numHandDofs()) = closed.hand;
    const robot::LinkPoses poses = robot::forwardKinematics(sdh, q);
    const Eigen::Isometry3d toObject =
        closed.palm * poses[static_cast<std::size_t>(sdh.palmLink())].inverse();
    for (std::size_t f = 0; f < 3; ++f) {
      const auto link = static_cast<std::size_t>(sdh.fingertips()[f].link);
      const robot::Clearance gap = surface.linkClearance(sdh.links()[link], toObject * poses[link]);
      EXPECT_LE(gap.distance, ClosingOptions{}.contact_distance);
      EXPECT_LE(surface.linkDepth(sdh.links()[link], toObject * poses[link], 1e-4), 1e-4);
      EXPECT_LE(std::abs(surface.nearest(closed.fingers[f].contact).signed_distance), 1e-9);
    }
  }
  EXPECT_EQ(touching, 5) << "too few leaves closed on to the mug to tell";
}

TEST(HandCloser, RefusesPosturesOfTheWrongSizeAndBadOptions) {
  const db::ObjectGeometry box = cube(0.05);
  const robot::ObjectSurface surface(box);
  const HandCloser closer(test::collisionOf(panda()), surface);
  EXPECT_THROW(closer.close(palmAroundOrigin(), Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(1)),
               InvalidArgument);
  EXPECT_THROW(
      closer.close(palmAroundOrigin(), Eigen::VectorXd::Constant(1, NAN), Eigen::VectorXd::Zero(1)),
      InvalidArgument);
  ClosingOptions bad;
  bad.contact_distance = 0.0;
  EXPECT_THROW(HandCloser(test::collisionOf(panda()), surface, bad), InvalidArgument);
}

}  // namespace
}  // namespace hfts::grasp
