#include "hfts_db/distance_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "core/invalid_argument.h"
#include "test_meshes.h"

namespace hfts::db {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// The reference: every triangle tried, inside where the winding number says.
double exactSignedDistance(const TriangleMesh& mesh, bool closed, const Eigen::Vector3d& p) {
  const double d = test::bruteForceDistance(mesh, p);
  return closed && std::abs(test::windingNumber(mesh, p)) > 0.5 ? -d : d;
}

TriangleMesh bundled(const std::string& file) {
  return loadMesh(test::bundledMeshDir() / file).mesh;
}

/// The cube without its top: open, so its distances are unsigned.
TriangleMesh openBox(double size) {
  TriangleMesh mesh = test::cube(size);
  Triangles kept(10, 3);
  kept << mesh.triangles.topRows(2), mesh.triangles.bottomRows(8);  // rows 2, 3 are z+
  mesh.triangles = kept;
  return mesh;
}

/// A box of edge lengths `size`, centred at the origin.
TriangleMesh box(const Eigen::Vector3d& size) {
  TriangleMesh mesh = test::cube(1.0);
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v)
    mesh.vertices.row(v) = mesh.vertices.row(v).cwiseProduct(size.transpose());
  return mesh;
}

Eigen::Vector3d randomNode(const DistanceGrid& grid, std::mt19937_64& rng) {
  std::array<std::uint32_t, 3> n;
  for (std::size_t c = 0; c < 3; ++c)
    n[c] = std::uniform_int_distribution<std::uint32_t>(0, grid.dims[c] - 1)(rng);
  return grid.node(n[0], n[1], n[2]);
}

float valueAt(const DistanceGrid& grid, const Eigen::Vector3d& node) {
  std::array<std::uint32_t, 3> n;
  for (int c = 0; c < 3; ++c)
    n[static_cast<std::size_t>(c)] =
        static_cast<std::uint32_t>(std::lround((node[c] - grid.origin[c]) / grid.spacing));
  return grid.values[grid.index(n[0], n[1], n[2])];
}

Eigen::Vector3d randomPoint(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                            std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  return lo + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(hi - lo);
}

/// Distance from p to the nearest node (the one lowerBound uses inside the box).
double toNearestNode(const DistanceGrid& grid, const Eigen::Vector3d& p) {
  const Eigen::Vector3d t = ((p - grid.origin) / grid.spacing).array().round();
  return (p - (grid.origin + grid.spacing * t)).norm();
}

struct Case {
  std::string name;
  TriangleMesh mesh;
  bool closed;
};

std::vector<Case> cases() {
  return {{"cube", test::cube(0.1, {0.01, -0.02, 0.03}), true},
          {"torus", bundled("torus.stl"), true},
          {"open box", openBox(0.1), false}};
}

TEST(DistanceGrid, NodeValuesAreTheExactDistancesRoundedDownToFloat) {
  std::mt19937_64 rng(1);
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const DistanceGrid grid = buildDistanceGrid(c.mesh, c.closed, {0.004, 0.02});
    EXPECT_EQ(grid.is_signed, c.closed);
    for (int i = 0; i < 400; ++i) {
      const Eigen::Vector3d node = randomNode(grid, rng);
      const double exact = exactSignedDistance(c.mesh, c.closed, node);
      const auto value = valueAt(grid, node);
      if (exact != 0.0 && std::abs(exact) < 1e-9) {  // on a face up to rounding: sign unsure
        EXPECT_LE(static_cast<double>(value), std::abs(exact)) << node.transpose();
        EXPECT_GE(static_cast<double>(value), -2.0 * std::abs(exact)) << node.transpose();
        continue;
      }
      // The largest float not above the exact distance.
      EXPECT_LE(static_cast<double>(value), exact) << node.transpose();
      EXPECT_GT(static_cast<double>(std::nextafter(value, std::numeric_limits<float>::infinity())),
                exact)
          << node.transpose();
    }
  }
}

TEST(DistanceGrid, LowerBoundNeverExceedsTheSignedDistanceAndIsTightInsideTheBox) {
  std::mt19937_64 rng(2);
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const DistanceGrid grid = buildDistanceGrid(c.mesh, c.closed, {0.004, 0.02});
    for (int i = 0; i < 1500; ++i) {
      const Eigen::Vector3d p = randomPoint(grid.origin, grid.boxMax(), rng);
      const double exact = exactSignedDistance(c.mesh, c.closed, p);
      const double bound = grid.lowerBound(p);
      EXPECT_LE(bound, exact + 1e-12) << p.transpose();  // 1e-12: rounding of the reference
      // 1-Lipschitz on both sides of the nearest node g: exact - 2 |p - g| at worst,
      // which is sqrt(3) spacing (1e-6 covers the float values).
      EXPECT_GE(bound, exact - 2.0 * toNearestNode(grid, p) - 1e-6) << p.transpose();
      EXPECT_GE(bound, exact - std::sqrt(3.0) * grid.spacing - 1e-6) << p.transpose();
    }
  }
}

TEST(DistanceGrid, LowerBoundIsTheNodeValueAtANode) {
  const DistanceGrid grid = buildDistanceGrid(test::cube(0.1), true, {0.005, 0.01});
  std::mt19937_64 rng(3);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d node = randomNode(grid, rng);
    EXPECT_EQ(grid.lowerBound(node), static_cast<double>(valueAt(grid, node)));
  }
}

TEST(DistanceGrid, LowerBoundOutsideTheBoxIsValidAndAtLeastTheDistanceToTheBox) {
  std::mt19937_64 rng(4);
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const DistanceGrid grid = buildDistanceGrid(c.mesh, c.closed, {0.004, 0.01});
    DistanceGrid withoutBoundaryMin = grid;
    withoutBoundaryMin.boundary_min = -std::numeric_limits<float>::infinity();
    const Eigen::Vector3d wide(0.3, 0.3, 0.3);
    int outside = 0;
    for (int i = 0; i < 1500; ++i) {
      const Eigen::Vector3d p = randomPoint(grid.origin - wide, grid.boxMax() + wide, rng);
      const Eigen::Vector3d q = p.cwiseMax(grid.origin).cwiseMin(grid.boxMax());
      if (q == p) continue;
      ++outside;
      const double exact = exactSignedDistance(c.mesh, c.closed, p);
      const double bound = grid.lowerBound(p);
      EXPECT_LE(bound, exact + 1e-12) << p.transpose();
      EXPECT_GE(bound, (p - q).norm()) << p.transpose();
      // Without the faces' minimum the bound is weaker, and still valid.
      const double weaker = withoutBoundaryMin.lowerBound(p);
      EXPECT_LE(weaker, bound) << p.transpose();
      EXPECT_GE(weaker, (p - q).norm()) << p.transpose();
    }
    EXPECT_GT(outside, 1000);
  }
}

TEST(DistanceGrid, LowerBoundBeyondAFaceIsTheDistanceUpToTheSpacing) {
  const TriangleMesh cube = test::cube(0.1);
  const DistanceGrid grid = buildDistanceGrid(cube, true, {0.0041, 0.03});
  for (const double beyond : {0.001, 0.02, 0.5}) {
    const Eigen::Vector3d p(grid.boxMax().x() + beyond, 0.003, -0.002);
    const double exact = test::bruteForceDistance(cube, p);
    EXPECT_LE(grid.lowerBound(p), exact);
    EXPECT_GE(grid.lowerBound(p), exact - 2.0 * grid.spacing) << beyond;
  }
}

TEST(DistanceGrid, BoundaryMinIsTheSmallestValueOnTheSixFaces) {
  const DistanceGrid grid = buildDistanceGrid(bundled("torus.stl"), true, {0.005, 0.01});
  float smallest = std::numeric_limits<float>::infinity();
  for (std::uint32_t z = 0; z < grid.dims[2]; ++z)
    for (std::uint32_t y = 0; y < grid.dims[1]; ++y)
      for (std::uint32_t x = 0; x < grid.dims[0]; ++x) {
        const bool face = x == 0 || y == 0 || z == 0 || x + 1 == grid.dims[0] ||
                          y + 1 == grid.dims[1] || z + 1 == grid.dims[2];
        if (face) smallest = std::min(smallest, grid.values[grid.index(x, y, z)]);
      }
  EXPECT_EQ(grid.boundary_min, smallest);
  EXPECT_EQ(boundaryMinimum(grid), smallest);
  EXPECT_GT(smallest, 0.01f - 1e-6f);  // the margin at least
  EXPECT_EQ(boundaryMinimum(DistanceGrid{}), -std::numeric_limits<float>::infinity());
}

TEST(DistanceGrid, LowerBoundJustOutsideTheBoxKeepsTheMargin) {
  // A point just beyond the box is at least the margin from the cube: the
  // bound must see that, not fall to 0 at the box.
  const DistanceGrid grid = buildDistanceGrid(test::cube(0.1), true, {0.005, 0.02});
  const Eigen::Vector3d top = grid.node(grid.dims[0] / 2, grid.dims[1] / 2, grid.dims[2] - 1);
  EXPECT_GT(grid.lowerBound(top + Eigen::Vector3d(0.0, 0.0, 0.001)), 0.02);
  EXPECT_GT(grid.lowerBound(grid.boxMax() + Eigen::Vector3d::Constant(0.001)),
            0.02 * std::sqrt(3.0));
}

TEST(DistanceGrid, NodesInsideClosedMeshesAreNegativeExactlyWhereTheWindingNumberSays) {
  // The mug is two closed parts that overlap inside the wall; the flipped
  // cube is wound inward.
  std::mt19937_64 rng(5);
  for (const Case& c : std::vector<Case>{{"torus", bundled("torus.stl"), true},
                                         {"mug", bundled("mug.ply"), true},
                                         {"inward cube", test::flipped(test::cube(0.1)), true}}) {
    SCOPED_TRACE(c.name);
    const DistanceGrid grid = buildDistanceGrid(c.mesh, true, {0.003, 0.01});
    int inside = 0;
    for (int i = 0; i < 1500; ++i) {
      const Eigen::Vector3d node = randomNode(grid, rng);
      if (test::bruteForceDistance(c.mesh, node) < 1e-6) continue;
      const bool in = std::abs(test::windingNumber(c.mesh, node)) > 0.5;
      EXPECT_EQ(valueAt(grid, node) < 0.0f, in) << node.transpose();
      inside += in ? 1 : 0;
    }
    EXPECT_GT(inside, 20);
  }
}

TEST(DistanceGrid, SignsAreRightWhereGridLinesRunThroughEdgesAndVertices) {
  // Nodes at multiples of 1/8 m hit the cube's faces, edges, corners and
  // face diagonals exactly (all binary fractions). The y- face is split
  // along x = z, so that the lines through (1, -1, 1) / 8 enter the cube
  // through a diagonal on each axis: unless exactly one of its two
  // triangles counts it, two of the three votes for that node are wrong.
  TriangleMesh cube = test::cube(0.5);
  cube.triangles.row(4) << 0, 1, 5;
  cube.triangles.row(5) << 0, 5, 4;
  const DistanceGrid grid = buildDistanceGrid(cube, true, {0.125, 0.25});
  EXPECT_LT(grid.lowerBound(Eigen::Vector3d(1, -1, 1) / 8), 0.0);
  ASSERT_EQ(grid.origin, Eigen::Vector3d::Constant(-0.5));
  for (std::uint32_t z = 0; z < grid.dims[2]; ++z)
    for (std::uint32_t y = 0; y < grid.dims[1]; ++y)
      for (std::uint32_t x = 0; x < grid.dims[0]; ++x) {
        const Eigen::Vector3d p = grid.node(x, y, z);
        const double outside = (p.cwiseAbs().array() - 0.25).cwiseMax(0.0).matrix().norm();
        const double exact = outside > 0.0 ? outside : p.cwiseAbs().maxCoeff() - 0.25;
        const auto value = static_cast<double>(grid.values[grid.index(x, y, z)]);
        EXPECT_EQ(value < 0.0, exact < 0.0) << p.transpose();
        EXPECT_EQ(value == 0.0, exact == 0.0) << p.transpose();
        EXPECT_NEAR(value, exact, 1e-7) << p.transpose();
      }
}

TEST(DistanceGrid, OpenMeshesGetUnsignedDistances) {
  const TriangleMesh mesh = openBox(0.1);
  const DistanceGrid grid = buildDistanceGrid(mesh, false, {0.005, 0.01});
  EXPECT_FALSE(grid.is_signed);
  for (float v : grid.values) EXPECT_GE(v, 0.0f);
  // The middle of the open box is about 5 cm from its walls, not inside anything.
  const Eigen::Vector3d middle = grid.node(grid.dims[0] / 2, grid.dims[1] / 2, grid.dims[2] / 2);
  EXPECT_LT(middle.norm(), 0.005);
  EXPECT_NEAR(grid.lowerBound(middle), test::bruteForceDistance(mesh, middle), 1e-8);
  EXPECT_GT(grid.lowerBound(middle), 0.045);
}

TEST(DistanceGrid, CoversTheBoundingBoxPlusTheMarginCentredOnIt) {
  const TriangleMesh mesh = box({0.2, 0.1, 0.05});
  const DistanceGrid grid = buildDistanceGrid(mesh, true, {0.0071, 0.02});
  const Eigen::Vector3d lo(-0.12, -0.07, -0.045), hi(0.12, 0.07, 0.045);
  EXPECT_TRUE((grid.origin.array() <= lo.array()).all()) << grid.origin.transpose();
  EXPECT_TRUE((grid.boxMax().array() >= hi.array()).all()) << grid.boxMax().transpose();
  EXPECT_LT(((grid.origin + grid.boxMax()) / 2).norm(), 1e-12);
  EXPECT_EQ(grid.dims, (std::array<std::uint32_t, 3>{35, 21, 14}));  // ceil(span / 7.1 mm) + 1
  EXPECT_EQ(grid.values.size(), 35u * 21u * 14u);
}

TEST(DistanceGrid, AFlatMeshStillGetsTwoNodesAlongEachAxis) {
  const DistanceGrid grid = buildDistanceGrid(test::square(0.1, 0.0), false, {0.01, 0.0});
  EXPECT_EQ(grid.dims[2], 2u);
  EXPECT_LE(grid.origin.z(), 0.0);
  EXPECT_GE(grid.boxMax().z(), 0.0);
}

TEST(DistanceGrid, AutomaticSpacingIsTheLongestSideOver64AtLeastAMillimetreWithinTheBudget) {
  EXPECT_EQ(buildDistanceGrid(box({0.64, 0.1, 0.1}), true, {0.0, 0.0}).spacing, 0.01);
  EXPECT_EQ(buildDistanceGrid(test::cube(0.02), true, {0.0, 0.0}).spacing, 0.001);
  // With the default 3 cm margin a 10 cm cube at 1.6 mm would need 1.1 M nodes.
  const DistanceGrid coarser = buildDistanceGrid(test::cube(0.1), true);
  EXPECT_GT(coarser.spacing, 0.1 / 64);
  EXPECT_LE(coarser.values.size(), kAutomaticGridNodes);
  EXPECT_GT(coarser.values.size(), kAutomaticGridNodes / 2);
}

TEST(DistanceGrid, BadOptionsAndMeshesAreRejectedNamingTheField) {
  const TriangleMesh cube = test::cube(0.1);
  auto expectField = [&](const TriangleMesh& mesh, DistanceGridOptions options,
                         const std::string& field) {
    try {
      buildDistanceGrid(mesh, true, options);
      ADD_FAILURE() << "no error for " << field;
    } catch (const InvalidArgument& e) {
      EXPECT_EQ(e.field(), field) << e.what();
    }
  };
  expectField(cube, {-0.01, 0.03}, "DistanceGridOptions::spacing");
  expectField(cube, {kInfinity, 0.03}, "DistanceGridOptions::spacing");
  expectField(cube, {1e-5, 0.03}, "DistanceGridOptions::spacing");  // 4e9 nodes
  expectField(cube, {0.0, -1.0}, "DistanceGridOptions::margin");
  expectField(cube, {0.0, std::nan("")}, "DistanceGridOptions::margin");
  expectField(TriangleMesh{}, {}, "mesh");
  TriangleMesh broken = cube;
  broken.vertices(3, 1) = std::nan("");
  expectField(broken, {}, "mesh");
}

TEST(DistanceGrid, AnEmptyGridProvesNothing) {
  const DistanceGrid empty;
  EXPECT_TRUE(empty.empty());
  EXPECT_EQ(empty.lowerBound(Eigen::Vector3d::Zero()), -kInfinity);
  const DistanceGrid grid = buildDistanceGrid(test::cube(0.1), true, {0.01, 0.01});
  EXPECT_FALSE(grid.empty());
  EXPECT_EQ(grid.lowerBound(Eigen::Vector3d(std::nan(""), 0.0, 0.0)), -kInfinity);
}

}  // namespace
}  // namespace hfts::db
