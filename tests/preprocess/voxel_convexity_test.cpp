#include "voxel_convexity.h"

#include <gtest/gtest.h>

#include "test_meshes.h"

namespace hfts::preprocess {
namespace {

using test::block;
using test::merged;

/// A square frame lying flat: 10 x 10 cm outside, a 6 x 6 cm hole, 2 cm tall.
TriangleMesh frame() {
  TriangleMesh m = block({0, 0, 0}, {0.1, 0.02, 0.02});
  m = merged(m, block({0, 0.08, 0}, {0.1, 0.1, 0.02}));
  m = merged(m, block({0, 0, 0}, {0.02, 0.1, 0.02}));
  return merged(m, block({0.08, 0, 0}, {0.1, 0.1, 0.02}));
}

/// Voxels whose centres lie in the box [lo, hi].
std::int64_t centresIn(const SolidLattice& lattice, const Eigen::Vector3d& lo,
                       const Eigen::Vector3d& hi) {
  std::int64_t n = 0;
  const VoxelBox w = lattice.whole();
  for (int k = w.lo[2]; k <= w.hi[2]; ++k)
    for (int j = w.lo[1]; j <= w.hi[1]; ++j)
      for (int i = w.lo[0]; i <= w.hi[0]; ++i) {
        const Eigen::Vector3d c(lattice.centre(0, i), lattice.centre(1, j), lattice.centre(2, k));
        n += (c.array() > lo.array()).all() && (c.array() < hi.array()).all() ? 1 : 0;
      }
  return n;
}

TEST(VoxelConvexity, ABlockIsConvexAndSoIsEveryCutOfIt) {
  const TriangleMesh box = block({0, 0, 0}, {0.1, 0.05, 0.03});
  const SolidLattice lattice(box, 32);
  const VoxelSet voxels(lattice, lattice.whole());
  EXPECT_EQ(voxels.measure().excess, 0);
  EXPECT_EQ(voxels.measure().count, centresIn(lattice, {0, 0, 0}, {0.1, 0.05, 0.03}));
  for (int axis = 0; axis < 3; ++axis)
    for (const auto& sides : voxels.cuts(axis)) {
      EXPECT_EQ(sides[0].excess + sides[1].excess, 0);
      EXPECT_EQ(sides[0].count + sides[1].count, voxels.measure().count);
    }
  // The box of voxels shrinks to the solid: one empty layer each side.
  EXPECT_EQ(voxels.box().lo[0], lattice.whole().lo[0] + 1);
  EXPECT_EQ(voxels.box().hi[2], lattice.whole().hi[2] - 1);
}

TEST(VoxelConvexity, AFramesExcessIsItsHoleAndNoSingleCutTakesItAway) {
  const TriangleMesh f = frame();
  const SolidLattice lattice(f, 40);
  const VoxelSet voxels(lattice, lattice.whole());
  // Every slab direction sees the hole filled: x and y slabs cross both
  // bars, z slabs ring it.
  const std::int64_t hole = centresIn(lattice, {0.02, 0.02, 0}, {0.08, 0.08, 0.02});
  EXPECT_GT(hole, 1000);
  EXPECT_EQ(voxels.measure().excess, hole);
  std::int64_t best = hole;
  for (int axis = 0; axis < 3; ++axis)
    for (const auto& sides : voxels.cuts(axis))
      if (sides[0].count > 0 && sides[1].count > 0)
        best = std::min(best, sides[0].excess + sides[1].excess);
  EXPECT_GT(best, hole / 2);  // one cut leaves a U at best, which holds the rest of the hole
}

TEST(VoxelConvexity, AnLIsConvexOnEitherSideOfItsInnerCorner) {
  const TriangleMesh l =
      merged(block({0, 0, 0}, {0.1, 0.04, 0.02}), block({0, 0, 0}, {0.02, 0.04, 0.06}));
  const SolidLattice lattice(l, 50);  // 2 mm voxels: faces between centres
  const VoxelSet voxels(lattice, lattice.whole());
  // Across y the L's hull holds the triangle of its notch below the line
  // from the arm's top to the base's end: about half the notch.
  const auto notch = static_cast<double>(centresIn(lattice, {0.02, 0, 0.02}, {0.1, 0.04, 0.06}));
  EXPECT_NEAR(static_cast<double>(voxels.measure().excess), notch / 2, 0.05 * notch);
  // The cut before the first layer above z = 2 cm.
  int at = voxels.frame().lo[2];
  while (lattice.centre(2, at) < 0.02) ++at;
  const auto& sides = voxels.cuts(2)[static_cast<std::size_t>(at - voxels.frame().lo[2] - 1)];
  EXPECT_EQ(sides[0].excess, 0);
  EXPECT_EQ(sides[1].excess, 0);
  EXPECT_EQ(sides[0].count, centresIn(lattice, {0, 0, 0}, {0.1, 0.04, 0.02}));
}

}  // namespace
}  // namespace hfts::preprocess
