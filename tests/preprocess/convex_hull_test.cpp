#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "preprocess/center_of_mass.h"
#include "preprocess/convex_hull.h"
#include "preprocess/object_geometry.h"
#include "test_meshes.h"

namespace hfts::preprocess {
namespace {

TEST(ConvexHull, OfACubeHasEightVerticesAndOutwardPlanes) {
  const Eigen::Vector3d centre(0.1, -0.2, 0.3);
  const ConvexHull hull(test::cube(0.1, centre).vertices, "cube");
  EXPECT_EQ(hull.vertices().rows(), 8);
  EXPECT_EQ(hull.faces().rows(), 12);
  EXPECT_NEAR(hull.depth(centre), 0.05, 1e-12);
  EXPECT_NEAR(hull.depth(centre + Eigen::Vector3d(0.05, 0, 0)), 0.0, 1e-12);
  EXPECT_NEAR(hull.depth(centre + Eigen::Vector3d(0.07, 0, 0)), -0.02, 1e-12);
  EXPECT_TRUE(hull.centroid().isApprox(centre, 1e-12));
}

TEST(ConvexHull, InteriorPointsDoNotChangeIt) {
  const TriangleMesh mesh = test::merged(test::cube(0.1), test::cube(0.05));
  EXPECT_EQ(ConvexHull(mesh.vertices, "m").vertices().rows(), 8);
}

TEST(ConvexHull, PointsInARowOnItsEdgesGiveOneHullInAnyInputOrder) {
  // A frustum of a 24-gon whose slanted edges each hold five points in a
  // row (like a basin's straight wall): CGAL's triangulation of such
  // facets, slivers included, depends on the input order; the stored hull
  // must not.
  Vertices points(24 * 5, 3);
  for (int k = 0; k < 24; ++k)
    for (int j = 0; j < 5; ++j) {
      const double a = 2 * M_PI * k / 24, r = 0.05 + 0.01 * j;
      points.row(5 * k + j) << r * std::cos(a), r * std::sin(a), 0.02 * j;
    }
  const ConvexHull first(points, "frustum");
  Vertices shuffled = points;
  std::mt19937 rng(3);
  for (int round = 0; round < 5; ++round) {
    for (Eigen::Index i = shuffled.rows() - 1; i > 0; --i)
      shuffled.row(i).swap(shuffled.row(std::uniform_int_distribution<Eigen::Index>(0, i)(rng)));
    const ConvexHull again(shuffled, "frustum");
    EXPECT_EQ(again.vertices(), first.vertices());
    EXPECT_EQ(again.faces(), first.faces());
  }
  // Every facet is covered: the hull's volume is the frustum's.
  double volume = 0;
  for (Eigen::Index f = 0; f < first.faces().rows(); ++f) {
    const Eigen::Vector3d a = first.vertices().row(first.faces()(f, 0)).transpose();
    const Eigen::Vector3d b = first.vertices().row(first.faces()(f, 1)).transpose();
    const Eigen::Vector3d c = first.vertices().row(first.faces()(f, 2)).transpose();
    volume += a.dot(b.cross(c)) / 6;
  }
  const auto polygon = [](double r) { return 0.5 * 24 * r * r * std::sin(2 * M_PI / 24); };
  const double h = 0.08, a0 = polygon(0.05), a1 = polygon(0.09);
  EXPECT_NEAR(volume, h / 3 * (a0 + a1 + std::sqrt(a0 * a1)), 1e-12);
}

TEST(ConvexHull, PointsOnItsFacetsAreNotCornersInAnyInputOrder) {
  // A box sampled on its faces and edges as well as its corners (like a
  // flat base whose centre is a mesh vertex): CGAL may keep such points as
  // hull vertices depending on the input order; the stored hull is the
  // eight corners and twelve triangles whatever the order.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> inside(-0.04, 0.04);
  Vertices points(8 + 60, 3);
  for (int c = 0; c < 8; ++c)
    points.row(c) << (c & 1 ? 0.05 : -0.05), (c & 2 ? 0.03 : -0.03), (c & 4 ? 0.02 : -0.02);
  for (int i = 8; i < points.rows(); ++i) {
    const Eigen::Vector3d half(0.05, 0.03, 0.02);
    Eigen::Vector3d p(inside(rng) / 0.04 * half.x(), inside(rng) / 0.04 * half.y(),
                      inside(rng) / 0.04 * half.z());
    p(i % 3) = (i % 2 ? 1 : -1) * half(i % 3);                              // on a face
    if (i % 4 == 0) p((i + 1) % 3) = (i % 8 ? 1 : -1) * half((i + 1) % 3);  // on an edge
    points.row(i) = p.transpose();
  }
  const ConvexHull first(points, "box");
  EXPECT_EQ(first.vertices().rows(), 8);
  EXPECT_EQ(first.faces().rows(), 12);
  for (int round = 0; round < 10; ++round) {
    Vertices shuffled = points;
    for (Eigen::Index i = shuffled.rows() - 1; i > 0; --i)
      shuffled.row(i).swap(shuffled.row(std::uniform_int_distribution<Eigen::Index>(0, i)(rng)));
    const ConvexHull again(shuffled, "box");
    EXPECT_EQ(again.vertices(), first.vertices());
    EXPECT_EQ(again.faces(), first.faces());
  }
  EXPECT_NEAR(first.depth(Eigen::Vector3d::Zero()), 0.02, 1e-15);
}

TEST(ConvexHull, FlatPointsAreRejected) {
  EXPECT_THROW(ConvexHull(test::square(0.1, 0.0).vertices, "flat"), MeshError);
}

TEST(ObjectGeometry, ClosedMeshUsesTheVolumeCentroid) {
  // An L of two cubes: the volume centroid differs from the hull centroid.
  const TriangleMesh mesh =
      test::merged(test::cube(0.1), test::cube(0.1, Eigen::Vector3d(0.1, 0, 0)));
  const TriangleMesh l = test::merged(mesh, test::cube(0.1, Eigen::Vector3d(0, 0.1, 0)));
  const ConvexHull hull(l.vertices, "L");
  const db::ObjectGeometry g = objectGeometry(l, true, hull, centerOfMass(l, true, hull));
  EXPECT_NEAR(g.volume, 3e-3, 1e-12);
  EXPECT_TRUE(g.center_of_mass.isApprox(Eigen::Vector3d(0.1 / 3, 0.1 / 3, 0), 1e-9));
  EXPECT_FALSE(g.center_of_mass.isApprox(hull.centroid(), 1e-3));
  // rho: the farthest corner from the centroid.
  const Eigen::Vector3d corner(0.15, -0.05, 0.05);
  EXPECT_NEAR(g.rho, (corner - g.center_of_mass).norm(), 1e-9);
}

TEST(ObjectGeometry, RecordsHowTheCentreOfMassWasFound) {
  const TriangleMesh cube = test::cube(0.1, Eigen::Vector3d(0.2, 0, 0));
  const ConvexHull hull(cube.vertices, "cube");
  EXPECT_EQ(objectGeometry(cube, true, hull, centerOfMass(cube, true, hull)).center_of_mass_method,
            db::CenterOfMassMethod::kClosedMesh);
  // Without one face the cube is nearly closed: capped, the same solid.
  TriangleMesh open = cube;
  open.triangles.conservativeResize(10, 3);
  const db::ObjectGeometry g = objectGeometry(open, false, hull, centerOfMass(open, false, hull));
  EXPECT_FALSE(g.closed);
  EXPECT_EQ(g.center_of_mass_method, db::CenterOfMassMethod::kRepairedMesh);
  EXPECT_NEAR(g.volume, 1e-3, 1e-15);
  EXPECT_TRUE(g.center_of_mass.isApprox(Eigen::Vector3d(0.2, 0, 0), 1e-12));
  EXPECT_NEAR(g.rho, std::sqrt(3.0) * 0.05, 1e-12);
  // A single face bounds nothing: the hull's centroid, no volume.
  open.triangles.conservativeResize(2, 3);
  const db::ObjectGeometry sheet =
      objectGeometry(open, false, hull, centerOfMass(open, false, hull));
  EXPECT_EQ(sheet.center_of_mass_method, db::CenterOfMassMethod::kConvexHull);
  EXPECT_EQ(sheet.volume, 0.0);
  EXPECT_TRUE(sheet.center_of_mass.isApprox(hull.centroid(), 1e-12));
}

TEST(ConvexHull, IsShallowAgreesWithDepthInside) {
  const TriangleMesh mesh = test::merged(test::cube(0.1), test::cube(0.1, {0.1, 0.05, 0.02}));
  const ConvexHull hull(mesh.vertices, "two cubes");
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.05, 0.15);
  int inside = 0;
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng) / 2);
    const double depth = hull.depth(p);
    if (depth < 0.0 || std::abs(depth - 0.01) < 1e-5) continue;
    EXPECT_EQ(hull.isShallow(p, 0.01), depth <= 0.01) << p.transpose();
    ++inside;
  }
  EXPECT_GT(inside, 300);
}

}  // namespace
}  // namespace hfts::preprocess
