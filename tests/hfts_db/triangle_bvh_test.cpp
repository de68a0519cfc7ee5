#include "hfts_db/triangle_bvh.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "test_meshes.h"

namespace hfts::db {
namespace {

using test::bruteForceDistance;

TEST(ClosestPointOnTriangle, CoversFaceEdgeAndVertexRegions) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_TRUE(
      closestPointOnTriangle({0.2, 0.2, 1}, a, b, c).isApprox(Eigen::Vector3d(0.2, 0.2, 0)));
  EXPECT_TRUE(closestPointOnTriangle({-1, -1, 0}, a, b, c).isApprox(a));
  EXPECT_TRUE(closestPointOnTriangle({2, -1, 0}, a, b, c).isApprox(b));
  EXPECT_TRUE(closestPointOnTriangle({0.5, -1, 3}, a, b, c).isApprox(Eigen::Vector3d(0.5, 0, 0)));
  EXPECT_TRUE(closestPointOnTriangle({1, 1, 0}, a, b, c).isApprox(Eigen::Vector3d(0.5, 0.5, 0)));
}

TEST(TriangleBvh, IsWithinAgreesWithBruteForce) {
  const TriangleMesh mesh = test::merged(test::cube(0.1), test::cube(0.04, {0.2, 0, 0}));
  const TriangleBvh bvh(mesh);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.1, 0.3);
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng) / 2, u(rng) / 2);
    const double d = bruteForceDistance(mesh, p);
    const double radius = 0.02;
    if (std::abs(d - radius) < 1e-5) continue;  // single precision inside Embree
    EXPECT_EQ(bvh.isWithin(p, radius), d <= radius) << p.transpose();
    ++checked;
  }
  EXPECT_GT(checked, 1900);
}

TEST(TriangleBvh, ClosestPointIsTheBruteForceMinimumWithAnyHint) {
  const TriangleMesh mesh = test::merged(test::cube(0.1), test::cube(0.04, {0.2, 0, 0}));
  const TriangleBvh bvh(mesh);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-0.3, 0.5);
  std::uniform_int_distribution<std::uint32_t> triangle(0, 23);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng) / 2, u(rng) / 2);
    const ClosestPoint nearest = bvh.closestPoint(p, triangle(rng));
    // Equal, not near: the same double computation decides, Embree only culls.
    EXPECT_EQ(nearest.distance, bruteForceDistance(mesh, p)) << p.transpose();
    EXPECT_NEAR((nearest.point - p).norm(), nearest.distance, 1e-15);
    const Eigen::Index t = nearest.triangle;
    const Eigen::Vector3d onTriangle = closestPointOnTriangle(
        p, mesh.vertices.row(mesh.triangles(t, 0)), mesh.vertices.row(mesh.triangles(t, 1)),
        mesh.vertices.row(mesh.triangles(t, 2)));
    EXPECT_EQ(onTriangle, nearest.point);
  }
}

TEST(TriangleBvh, ClosestPointOfAnEmptyMeshIsInfinitelyFar) {
  const TriangleBvh bvh(TriangleMesh{});
  EXPECT_EQ(bvh.closestPoint(Eigen::Vector3d::Zero()).distance,
            std::numeric_limits<double>::infinity());
}

TEST(TriangleBvh, RaysEscapeOnlyWhereNothingIsHit) {
  const TriangleBvh bvh(test::cube(0.1));
  EXPECT_FALSE(bvh.escapes({0, 0, 0}, {1, 0, 0}));     // from inside
  EXPECT_FALSE(bvh.escapes({-1, 0, 0}, {1, 0, 0}));    // towards the cube
  EXPECT_TRUE(bvh.escapes({-1, 0, 0}, {-1, 0, 0}));    // away from it
  EXPECT_TRUE(bvh.escapes({0, 0, 0.051}, {0, 0, 1}));  // just outside a face
}

}  // namespace
}  // namespace hfts::db
