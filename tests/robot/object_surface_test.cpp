#include "robot/object_surface.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/invalid_argument.h"
#include "hfts_db/distance_grid.h"
#include "test_meshes.h"

namespace hfts::robot {
namespace {

/// A cube of side 0.1 m centred at the origin, with or without its signed
/// distance grid.
db::ObjectGeometry cubeGeometry(bool withGrid) {
  const TriangleMesh mesh = test::cube(0.1);
  db::ObjectGeometry g = test::meshObject(mesh);
  if (withGrid) g.distance_grid = db::buildDistanceGrid(mesh, true, {0.005, 0.03});
  return g;
}

CollisionShape sphere(double radius) {
  CollisionShape s;
  s.type = CollisionShape::Type::kSphere;
  s.size = {radius, 0, 0};
  return s;
}

CollisionShape cylinder(double radius, double length) {
  CollisionShape s;
  s.type = CollisionShape::Type::kCylinder;
  s.size = {radius, length, 0};
  return s;
}

Eigen::Isometry3d at(const Eigen::Vector3d& p) {
  return Eigen::Isometry3d(Eigen::Translation3d(p));
}

TEST(ObjectSurface, SignsDistancesAndGivesTheMeshNormalOnFacesEdgesAndCorners) {
  const ObjectSurface surface(cubeGeometry(false));
  const SurfacePoint outside = surface.nearest({0.08, 0.0, 0.01});
  EXPECT_NEAR(outside.signed_distance, 0.03, 1e-12);
  EXPECT_TRUE(outside.point.isApprox(Eigen::Vector3d(0.05, 0.0, 0.01), 1e-12));
  EXPECT_TRUE(outside.normal.isApprox(Eigen::Vector3d::UnitX(), 1e-12));
  EXPECT_NEAR(surface.nearest({0.0, -0.04, 0.01}).signed_distance, -0.01, 1e-12);
  // Beyond an edge: the mean of its two faces; beyond a corner: of three.
  const SurfacePoint edge = surface.nearest({0.06, 0.06, 0.0});
  EXPECT_TRUE(edge.normal.isApprox(Eigen::Vector3d(1, 1, 0).normalized(), 1e-9)) << edge.normal;
  EXPECT_NEAR(edge.signed_distance, std::sqrt(2.0) * 0.01, 1e-12);
  const SurfacePoint corner = surface.nearest({0.07, -0.07, 0.07});
  EXPECT_TRUE(corner.normal.isApprox(Eigen::Vector3d(1, -1, 1).normalized(), 1e-9));
  EXPECT_NEAR(corner.signed_distance, std::sqrt(3.0) * 0.02, 1e-12);
}

TEST(ObjectSurface, AShapesSmallestSignedDistanceIsItsClearanceOrItsDepth) {
  for (const bool withGrid : {false, true}) {
    SCOPED_TRACE(withGrid ? "with the distance grid" : "without a grid");
    const ObjectSurface surface(cubeGeometry(withGrid));
    constexpr double kTolerance = 1e-4;
    // A sphere 7 mm off the +x face, one 3 mm into it.
    const ShapeDistance apart = surface.shapeDistance(sphere(0.01), at({0.067, 0, 0}), kTolerance);
    EXPECT_LE(apart.lower, 0.007 + 1e-12);
    EXPECT_GE(apart.lower, 0.007 - kTolerance);
    const ShapeDistance in = surface.shapeDistance(sphere(0.01), at({0.057, 0.01, 0}), kTolerance);
    EXPECT_LE(in.lower, -0.003 + 1e-12);
    EXPECT_GE(in.lower, -0.003 - kTolerance);
    EXPECT_NEAR(in.surface.point.x(), 0.05, 1e-9);
    // A cylinder lying on the top face 2 mm deep along its whole length: a
    // line of points all at the minimum.
    Eigen::Isometry3d lying = at({0.0, 0.0, 0.05 + 0.006 - 0.002});
    lying.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
    const ShapeDistance line = surface.shapeDistance(cylinder(0.006, 0.08), lying, kTolerance);
    EXPECT_LE(line.lower, -0.002 + 1e-12);
    EXPECT_GE(line.lower, -0.002 - kTolerance);
    // Asked only "deeper than 1 mm?", it stops early with a bound below -1 mm.
    EXPECT_LT(surface.shapeDistance(cylinder(0.006, 0.08), lying, kTolerance, -0.001).lower,
              -0.001);
  }
}

TEST(ObjectSurface, ALinksClearanceIsFclsDistanceAndItsDepthIsZeroWhenApart) {
  const ObjectSurface surface(cubeGeometry(true));
  Link link;
  link.shapes = {sphere(0.01), sphere(0.005)};
  link.shapes[1].origin = at({0.0, 0.0, -0.01});
  // The second sphere is nearer the top face (z = 0.05): 0.06 - 0.005 - 0.05.
  const Clearance apart = surface.linkClearance(link, at({0.0, 0.0, 0.07}));
  EXPECT_NEAR(apart.distance, 0.005, 1e-9);
  EXPECT_TRUE(apart.on_surface.isApprox(Eigen::Vector3d(0, 0, 0.05), 1e-6)) << apart.on_surface;
  EXPECT_NEAR(apart.on_link.z(), 0.055, 1e-6);
  EXPECT_EQ(surface.linkDepth(link, at({0.0, 0.0, 0.07}), 5e-5), 0.0);
  // Lowered by 6 mm: touching, 1 mm deep.
  const Eigen::Isometry3d pressed = at({0.0, 0.0, 0.064});
  EXPECT_EQ(surface.linkClearance(link, pressed).distance, 0.0);
  EXPECT_NEAR(surface.linkDepth(link, pressed, 1e-4), 0.001, 1e-4 + 1e-12);
  EXPECT_GE(surface.linkDepth(link, pressed, 1e-4), 0.001 - 1e-12);  // never underestimated
}

TEST(ObjectSurface, RefusesAMeshWithoutTrianglesAndABadTolerance) {
  EXPECT_THROW(ObjectSurface(db::ObjectGeometry{}), InvalidArgument);
  db::ObjectGeometry broken = cubeGeometry(false);
  broken.mesh_triangles(0, 0) = 1000;
  EXPECT_THROW(ObjectSurface{broken}, InvalidArgument);
  const ObjectSurface surface(cubeGeometry(false));
  EXPECT_THROW(surface.shapeDistance(sphere(0.01), at({0.2, 0, 0}), 0.0), InvalidArgument);
}

}  // namespace
}  // namespace hfts::robot
