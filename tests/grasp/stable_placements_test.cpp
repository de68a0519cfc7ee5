// Stable placements (grasp/stable_placements.h): the faces of an object's
// hull it stands on, rated by how far it must tilt before it tips, and the
// pose that puts it on a level support.
#include "grasp/stable_placements.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "bundled_objects.h"
#include "core/invalid_argument.h"
#include "test_meshes.h"

namespace hfts::grasp {
namespace {

/// A box object from corner lo to hi: its hull is the box.
db::ObjectGeometry boxObject(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                             const Eigen::Vector3d& centerOfMass) {
  const TriangleMesh mesh = test::block(lo, hi);
  db::ObjectGeometry g = test::meshObject(mesh);
  g.hull_vertices = mesh.vertices;
  g.hull_faces = mesh.triangles;
  g.center_of_mass = centerOfMass;
  return g;
}

TEST(StablePlacements, ABoxStandsOnEachOfItsSixFacesTheFlattestFirst) {
  // 10 x 6 x 20 cm, centre of mass in the middle.
  const db::ObjectGeometry box = boxObject(
      Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.1, 0.06, 0.2), Eigen::Vector3d(0.05, 0.03, 0.1));
  const std::vector<RestingFace> faces = stablePlacements(box);
  ASSERT_EQ(faces.size(), 6u);
  // Flat on a 10 x 20 face: 3 cm high, 5 cm from the nearest edge.
  EXPECT_NEAR(std::abs(faces[0].normal.y()), 1.0, 1e-12);
  EXPECT_NEAR(faces[0].height, 0.03, 1e-12);
  EXPECT_NEAR(faces[0].margin, 0.05, 1e-12);
  EXPECT_NEAR(faces[0].area, 0.02, 1e-12);
  EXPECT_EQ(faces[0].polygon.cols(), 4);
  // Upright on a 10 x 6 end last: 10 cm high, 3 cm from the nearest edge.
  EXPECT_NEAR(std::abs(faces[5].normal.z()), 1.0, 1e-12);
  EXPECT_NEAR(faces[5].tipping_angle, std::atan2(0.03, 0.1), 1e-12);
  for (std::size_t i = 1; i < faces.size(); ++i)
    EXPECT_GE(faces[i - 1].tipping_angle, faces[i].tipping_angle);
}

TEST(StablePlacements, AFaceTheCentreOfMassDoesNotProjectInsideIsLeftOut) {
  // The centre of mass 1 mm from the +x face: only the two x faces keep it
  // 2 mm inside their polygon.
  const db::ObjectGeometry box = boxObject(
      Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.1, 0.06, 0.2), Eigen::Vector3d(0.099, 0.03, 0.1));
  const std::vector<RestingFace> faces = stablePlacements(box);
  ASSERT_EQ(faces.size(), 2u);
  for (const RestingFace& face : faces) EXPECT_NEAR(std::abs(face.normal.x()), 1.0, 1e-12);
  PlacementOptions loose;
  loose.min_margin = 0.0;
  loose.min_tipping_angle = 0.0;
  EXPECT_EQ(stablePlacements(box, loose).size(), 6u);
}

TEST(StablePlacements, TheRestingPoseStandsTheFaceOnTheSupportUnderTheCentreOfMass) {
  const Eigen::Vector3d com(0.05, 0.03, 0.1);
  const db::ObjectGeometry box =
      boxObject(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.1, 0.06, 0.2), com);
  for (const RestingFace& face : stablePlacements(box)) {
    const Eigen::Isometry3d pose = restingPose(face, com, Eigen::Vector2d(0.4, -0.2), 0.7, 0.75);
    double lowest = 1e9;
    for (Eigen::Index v = 0; v < box.hull_vertices.rows(); ++v)
      lowest = std::min(lowest, (pose * box.hull_vertices.row(v).transpose()).z());
    EXPECT_NEAR(lowest, 0.75, 1e-12);
    EXPECT_NEAR((pose.linear() * face.normal - Eigen::Vector3d(0, 0, -1)).norm(), 0.0, 1e-12);
    const Eigen::Vector3d above = pose * com;
    EXPECT_NEAR(above.x(), 0.4, 1e-12);
    EXPECT_NEAR(above.y(), -0.2, 1e-12);
    EXPECT_NEAR(above.z(), 0.75 + face.height, 1e-12);
    for (Eigen::Index c = 0; c < face.polygon.cols(); ++c)
      EXPECT_NEAR((pose * face.polygon.col(c)).z(), 0.75, 1e-12);
  }
}

TEST(StablePlacements, BadOptionsAreRefusedByName) {
  const db::ObjectGeometry box =
      boxObject(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), Eigen::Vector3d::Constant(0.5));
  PlacementOptions bad;
  bad.min_margin = -1.0;
  test::expectErrorMentioning<InvalidArgument>([&] { stablePlacements(box, bad); },
                                               {"options.min_margin"});
  bad = {};
  bad.contact_tolerance = std::nan("");
  test::expectErrorMentioning<InvalidArgument>([&] { stablePlacements(box, bad); },
                                               {"options.contact_tolerance"});
}

TEST(StablePlacements, TheMugAndTheBottleStandUpright) {
  // Both stand on their bottom (the lowest z of the mesh as bundled) as
  // well as on their top rim, and the upright ways come among the first.
  for (const char* name : {"mug", "bottle"}) {
    const db::ObjectDatabase& object = test::bundledObjects().at(name);
    const std::vector<RestingFace> faces = stablePlacements(object.geometry);
    ASSERT_FALSE(faces.empty()) << name;
    bool upright = false;
    for (const RestingFace& face : faces) upright = upright || face.normal.z() < -0.999;
    EXPECT_TRUE(upright) << name;
  }
  // Every bundled object rests some way but those that roll: a ball, an
  // egg and a dowel (1 cm thick: on a facet of its side, or standing on
  // its end, it tips before it tilts 10 degrees).
  const std::set<std::string> rolling{"dowel", "egg", "small_ball"};
  for (const auto& [name, object] : test::bundledObjects())
    EXPECT_EQ(stablePlacements(object.geometry).empty(), rolling.count(name) > 0) << name;
}

}  // namespace
}  // namespace hfts::grasp
