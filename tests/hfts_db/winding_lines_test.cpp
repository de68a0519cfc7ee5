#include "hfts_db/winding_lines.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/invalid_argument.h"
#include "test_meshes.h"

namespace hfts::db {
namespace {

/// `n` x `n` lines along `axis`, `spacing` apart, centred on the origin.
LineLattice centredLattice(int axis, std::uint32_t n, double spacing) {
  LineLattice lattice;
  lattice.axis = axis;
  lattice.spacing = spacing;
  lattice.counts = {n, n};
  lattice.origin = Eigen::Vector3d::Constant(-spacing * (n - 1) / 2.0);
  return lattice;
}

std::size_t count(const WindingLines& lines, std::size_t line) {
  return static_cast<std::size_t>(lines.end(line) - lines.begin(line));
}

TEST(WindingLines, ACubeIsOneIntervalOnTheLinesThroughItAndNothingBeside) {
  // Lines 0.03 apart: those with |u|, |v| < 0.05 pass through the cube.
  for (int axis = 0; axis < 3; ++axis) {
    SCOPED_TRACE(axis);
    const WindingLines lines = windingLines(test::cube(0.1), centredLattice(axis, 7, 0.03));
    for (std::uint32_t j = 0; j < 7; ++j)
      for (std::uint32_t i = 0; i < 7; ++i) {
        const std::size_t line = lines.lattice.index(i, j);
        const bool through = std::abs(lines.lattice.coordinate(0, i)) < 0.05 &&
                             std::abs(lines.lattice.coordinate(1, j)) < 0.05;
        ASSERT_EQ(count(lines, line), through ? 1u : 0u) << i << " " << j;
        if (!through) continue;
        EXPECT_DOUBLE_EQ(lines.begin(line)->enter, -0.05);
        EXPECT_DOUBLE_EQ(lines.begin(line)->exit, 0.05);
      }
  }
}

TEST(WindingLines, APointIsInsideAfterTheEntryUpToAndIncludingTheExit) {
  const WindingLines lines = windingLines(test::cube(0.1), centredLattice(2, 1, 1.0));
  EXPECT_FALSE(lines.inside(0, -0.05));
  EXPECT_TRUE(lines.inside(0, -0.0499));
  EXPECT_TRUE(lines.inside(0, 0.05));
  EXPECT_FALSE(lines.inside(0, 0.0501));
  EXPECT_DOUBLE_EQ(lines.length(0, -1.0, 1.0), 0.1);
  EXPECT_DOUBLE_EQ(lines.length(0, 0.0, 1.0), 0.05);
  EXPECT_DOUBLE_EQ(lines.length(0, 0.2, 1.0), 0.0);
}

TEST(WindingLines, OverlappingPartsMergeAndInwardWindingStillCounts) {
  // Two cubes that overlap along z (winding 2 in the overlap) are one
  // stretch of solid; a cube wound inward (winding -1) is solid too; two
  // apart are two stretches.
  const LineLattice lattice = centredLattice(2, 1, 1.0);
  const WindingLines overlapping =
      windingLines(test::merged(test::cube(0.1), test::cube(0.1, {0, 0, 0.06})), lattice);
  ASSERT_EQ(count(overlapping, 0), 1u);
  EXPECT_DOUBLE_EQ(overlapping.begin(0)->enter, -0.05);
  EXPECT_DOUBLE_EQ(overlapping.begin(0)->exit, 0.11);
  EXPECT_DOUBLE_EQ(overlapping.overlap[0], 0.04);  // 0.01 .. 0.05, covered twice
  const WindingLines inward = windingLines(test::flipped(test::cube(0.1)), lattice);
  ASSERT_EQ(count(inward, 0), 1u);
  EXPECT_DOUBLE_EQ(inward.length(0, -1, 1), 0.1);
  const WindingLines apart =
      windingLines(test::merged(test::cube(0.1), test::cube(0.1, {0, 0, 0.2})), lattice);
  EXPECT_EQ(count(apart, 0), 2u);
  EXPECT_DOUBLE_EQ(apart.length(0, -1, 1), 0.2);
  EXPECT_EQ(apart.overlap[0], 0.0);
  EXPECT_EQ(inward.overlap[0], 0.0);
}

TEST(WindingLines, LinesThroughEdgesAndVerticesCrossTheSurfaceOnce) {
  // Lines 1/40 m apart run exactly through the cube's edges, its corners
  // and the diagonals of its faces (all binary fractions): each must see
  // the whole cube or nothing. The 3 x 3 lines strictly inside its
  // outline see it; those on the outline count as moved off it in one
  // fixed direction, so some of them do.
  for (int axis = 0; axis < 3; ++axis) {
    SCOPED_TRACE(axis);
    const WindingLines lines = windingLines(test::cube(0.1), centredLattice(axis, 9, 0.025));
    std::size_t through = 0;
    for (std::uint32_t j = 0; j < 9; ++j)
      for (std::uint32_t i = 0; i < 9; ++i) {
        const std::size_t line = lines.lattice.index(i, j);
        ASSERT_LE(count(lines, line), 1u);
        if (count(lines, line) == 0) continue;
        EXPECT_DOUBLE_EQ(lines.length(line, -1, 1), 0.1);
        ++through;
      }
    EXPECT_GE(through, 9u);
    EXPECT_LT(through, 25u);
  }
}

TEST(WindingLines, InsideAgreesWithTheGeneralisedWindingNumberOfTheMug) {
  // The mug's handle overlaps its wall: inside is where the winding number
  // is not 0, whether 1 or 2.
  const TriangleMesh mug = loadMesh(test::bundledMeshDir() / "mug.ply").mesh;
  LineLattice lattice;
  lattice.axis = 0;
  lattice.origin = Eigen::Vector3d(0.0, -0.041, -0.001);
  lattice.spacing = 0.0013;
  lattice.counts = {64, 80};
  const WindingLines lines = windingLines(mug, lattice);
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<std::uint32_t> pickI(0, 63), pickJ(0, 79);
  std::uniform_real_distribution<double> alongX(-0.045, 0.08);
  int inside = 0;
  for (int n = 0; n < 800; ++n) {
    const std::uint32_t i = pickI(rng), j = pickJ(rng);
    const Eigen::Vector3d p(alongX(rng), lattice.coordinate(0, i), lattice.coordinate(1, j));
    const double w = test::windingNumber(mug, p);
    EXPECT_EQ(lines.inside(lattice.index(i, j), p.x()), std::abs(w) > 0.5) << p.transpose();
    inside += std::abs(w) > 0.5 ? 1 : 0;
  }
  EXPECT_GT(inside, 40);
  std::size_t multiple = 0;  // lines through the handle and the body see both
  for (std::size_t l = 0; l < lattice.lines(); ++l) multiple += count(lines, l) > 2 ? 1 : 0;
  EXPECT_GT(multiple, 10u);
}

TEST(WindingLines, BadLatticesAndMeshesAreRejectedNamingTheField) {
  LineLattice lattice = centredLattice(2, 3, 0.01);
  lattice.axis = 3;
  test::expectErrorMentioning<InvalidArgument>([&] { windingLines(test::cube(0.1), lattice); },
                                               {"lattice.axis"});
  lattice = centredLattice(2, 3, 0.0);
  test::expectErrorMentioning<InvalidArgument>([&] { windingLines(test::cube(0.1), lattice); },
                                               {"lattice.spacing"});
  lattice = centredLattice(2, 3, 0.01);
  lattice.origin.x() = std::nan("");
  test::expectErrorMentioning<InvalidArgument>([&] { windingLines(test::cube(0.1), lattice); },
                                               {"lattice.origin"});
  TriangleMesh broken = test::cube(0.1);
  broken.triangles(0, 0) = 99;
  test::expectErrorMentioning<InvalidArgument>(
      [&] { windingLines(broken, centredLattice(2, 3, 0.01)); }, {"mesh"});
}

}  // namespace
}  // namespace hfts::db
