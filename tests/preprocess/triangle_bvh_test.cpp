#include "preprocess/triangle_bvh.h"

#include <gtest/gtest.h>

#include <random>

#include "preprocess/convex_hull.h"
#include "test_meshes.h"

namespace hfts::preprocess {
namespace {

double bruteForceDistance(const TriangleMesh& mesh, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(t, 0));
    const Eigen::Vector3d b = mesh.vertices.row(mesh.triangles(t, 1));
    const Eigen::Vector3d c = mesh.vertices.row(mesh.triangles(t, 2));
    best = std::min(best, (closestPointOnTriangle(p, a, b, c) - p).norm());
  }
  return best;
}

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

TEST(TriangleBvh, RaysEscapeOnlyWhereNothingIsHit) {
  const TriangleBvh bvh(test::cube(0.1));
  EXPECT_FALSE(bvh.escapes({0, 0, 0}, {1, 0, 0}));     // from inside
  EXPECT_FALSE(bvh.escapes({-1, 0, 0}, {1, 0, 0}));    // towards the cube
  EXPECT_TRUE(bvh.escapes({-1, 0, 0}, {-1, 0, 0}));    // away from it
  EXPECT_TRUE(bvh.escapes({0, 0, 0.051}, {0, 0, 1}));  // just outside a face
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
