#include "planner/grasp_validation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "bundled_objects.h"
#include "grasp/hand_map_builder.h"
#include "grasp/load_capacity.h"
#include "panda_cube.h"
#include "robot/kinematics.h"
#include "robot_fixture.h"
#include "test_meshes.h"

namespace hfts::planner {
namespace {

using test::panda;

/// A prism along x whose cross-section is a triangle standing on its apex:
/// apex at the origin, its top face `height` out along +z and as wide as
/// twice the height, so its sides lean 45 degrees away from the z axis.
TriangleMesh vee(double height, double length) {
  TriangleMesh m;
  const double h = height, l = length / 2;
  m.vertices.resize(6, 3);
  m.vertices << -l, 0, 0, -l, -h, h, -l, h, h, l, 0, 0, l, -h, h, l, h, h;
  m.triangles.resize(8, 3);
  m.triangles << 0, 1, 2,  // the end at -x
      3, 5, 4,             // the end at +x
      0, 4, 1, 0, 3, 4,    // the side at -y
      0, 5, 3, 0, 2, 5,    // the side at +y
      1, 5, 2, 1, 4, 5;    // the top
  return m;
}

/// The Panda at home with its jaws at `jaw` (m each), and where an object
/// must be for the midpoint between its fingertip points to be at the
/// object's origin, jaws along the object's y, fingers towards its +z.
struct PandaAroundObject {
  Eigen::VectorXd open, closed;
  Eigen::Isometry3d object_pose;
  PandaAroundObject() {
    open = panda().home();
    open.tail(1) << 0.04;
    closed = open;
    closed.tail(1) << 0.0;
    const robot::LinkPoses poses = robot::forwardKinematics(panda(), open);
    const robot::FingertipFrames tips = robot::fingertipFrames(panda(), poses);
    const Eigen::Isometry3d palm = poses[static_cast<std::size_t>(panda().palmLink())];
    object_pose = palm;
    object_pose.translation() = (tips.positions.col(0) + tips.positions.col(1)) / 2;
  }
};

TEST(GraspValidation,
     AGraspWithoutForceClosureAtItsContactsIsRejectedAndMinEpsilonRejectsAWeakOne) {
  // The jaws close on the vee's leaning sides (45 degrees, outside the
  // friction cone of mu 0.5 about the jaws' line): both pads touch, and
  // the squeeze pushes the vee out along +z: no force closure. On a 2 cm
  // cube in the same place they close on two parallel faces (the cube's
  // origin is inside it, where a jaw that starts apart from it, told so
  // by the distance grid, was once taken to be).
  std::map<std::string, db::ObjectDatabase> objects;
  objects.emplace("vee", preprocess::buildObjectDatabase(vee(0.03, 0.03), true,
                                                         test::fixtureParameters(), "vee")
                             .database);
  objects.emplace("cube", preprocess::buildObjectDatabase(test::cube(0.02), true,
                                                          test::fixtureParameters(), "cube")
                              .database);
  const PlanningWorld world(panda(), grasp::buildHandMap(panda(), grasp::handMapOptions(panda())),
                            std::move(objects));
  const PandaAroundObject at;
  ValidationRequest r;
  r.scene.target_pose = at.object_pose;
  r.pregrasp = at.open;
  r.grasp = at.closed;
  r.physics = false;

  r.scene.target_object = "vee";
  const Validation vee = validateGrasp(world, r);
  EXPECT_TRUE(vee.check.pads_touch) << vee.check.problem;
  EXPECT_TRUE(vee.check.clear);
  EXPECT_EQ(vee.check.epsilon, 0.0);
  EXPECT_EQ(vee.check.problem, "no force closure at the contacts the pads touch");
  EXPECT_FALSE(vee.holds());

  r.scene.target_object = "cube";
  const Validation cube = validateGrasp(world, r);
  EXPECT_TRUE(cube.check.valid()) << cube.check.problem;
  EXPECT_GT(cube.check.epsilon, r.check.min_epsilon);
  EXPECT_NEAR(cube.check.executed.tail(1)(0), 0.01, 2e-4);  // closed on to the faces
  // The same grasp against a min_epsilon above its epsilon.
  r.check.min_epsilon = 2 * cube.check.epsilon;
  const Validation weak = validateGrasp(world, r);
  EXPECT_FALSE(weak.check.valid());
  EXPECT_NE(weak.check.problem.find("below min_epsilon"), std::string::npos) << weak.check.problem;

  // The vee slips out between the jaws whatever they push: no load. The
  // 2 cm cube (8 g at water's density) is light for 35 N per jaw: beyond
  // the cap. At 16 t/m^3 (128 g, W = 1.26 N) the -z disturbance's 2 W
  // needs 2 mu F of the pads' friction: 17.5 N / W, less the linearised
  // pyramid's excess between its edges (it is around the cone).
  ASSERT_TRUE(vee.check.load_capacity.has_value());
  EXPECT_LT(*vee.check.load_capacity, 1e-6);
  ASSERT_TRUE(cube.check.load_capacity.has_value());
  EXPECT_EQ(*cube.check.load_capacity, grasp::kUnboundedLoad);
  r.check.min_epsilon = 0.0;
  r.simulation.density = 16000.0;
  const Validation dense = validateGrasp(world, r);
  ASSERT_TRUE(dense.check.load_capacity.has_value());
  const double weight = 8e-6 * 16000.0 * 9.81;
  EXPECT_GE(*dense.check.load_capacity, 17.5 / weight - 1e-6);
  EXPECT_LE(*dense.check.load_capacity, 17.5 / std::cos(M_PI / 8.0) / weight + 1e-6);
}

}  // namespace
}  // namespace hfts::planner
