#include "cut_search.h"

#include <gtest/gtest.h>

#include "test_meshes.h"

namespace hfts::preprocess {
namespace {

using test::block;
using test::merged;

TEST(CutSearch, AnLIsCutAlongItsArmsInnerFace) {
  // 1.6 mm voxels: the inner faces (x = 2 cm, z = 2 cm) lie between
  // centres, and the cut is moved onto them.
  const TriangleMesh l =
      merged(block({0, 0, 0}, {0.1, 0.04, 0.02}), block({0, 0, 0}, {0.02, 0.04, 0.06}));
  const SolidLattice lattice(l, 64);
  const CutSearch search(lattice, l);
  const std::optional<Cut> cut = search.choose(VoxelSet(lattice, lattice.whole()));
  ASSERT_TRUE(cut);
  EXPECT_NE(cut->axis, 1);
  EXPECT_EQ(cut->coordinate, 0.02);
  EXPECT_EQ(cut->sides[0].excess + cut->sides[1].excess, 0);
  EXPECT_LT(lattice.centre(cut->axis, cut->at - 1), 0.02);
  EXPECT_GE(lattice.centre(cut->axis, cut->at), 0.02);
}

TEST(CutSearch, ARingIsCutAcrossItsHoleThoughNoSingleCutHelps) {
  // A square frame lying flat: cutting it in z helps nothing now or after;
  // cutting across x or y leaves two Us, which one more cut each makes
  // convex.
  TriangleMesh f = block({0, 0, 0}, {0.1, 0.02, 0.02});
  f = merged(f, block({0, 0.08, 0}, {0.1, 0.1, 0.02}));
  f = merged(f, block({0, 0, 0}, {0.02, 0.1, 0.02}));
  f = merged(f, block({0.08, 0, 0}, {0.1, 0.1, 0.02}));
  const SolidLattice lattice(f, 40);
  const std::optional<Cut> cut = CutSearch(lattice, f).choose(VoxelSet(lattice, lattice.whole()));
  ASSERT_TRUE(cut);
  EXPECT_NE(cut->axis, 2);
}

TEST(CutSearch, CandidatesPartTheVoxelsFromTheRestOfALargerBox) {
  const TriangleMesh box = block({0, 0, 0}, {0.1, 0.05, 0.03});
  const SolidLattice lattice(box, 32);
  const VoxelSet voxels(lattice, lattice.whole());
  // A box reaching 2 cm beyond the solid in x: a cut at the voxels' last
  // face parts them from the empty rest.
  const Box3 bounds{{0, 0, 0}, {0.12, 0.05, 0.03}};
  bool trim = false;
  for (const Cut& c : CutSearch(lattice, box).candidates(voxels, bounds))
    trim = trim || (c.axis == 0 && c.coordinate == lattice.face(0, voxels.box().hi[0] + 1) &&
                    c.sides[1].count == 0);
  EXPECT_TRUE(trim);
  // Voxels too few to cut (at least two layers a side): no choice.
  const TriangleMesh thin = block({0, 0, 0}, {0.1, 0.01, 0.01});
  const SolidLattice fine(thin, 64);
  EXPECT_TRUE(CutSearch(fine, thin).choose(VoxelSet(fine, fine.whole())).has_value());
  VoxelBox one = VoxelSet(fine, fine.whole()).box();
  for (std::size_t c = 0; c < 3; ++c) one.hi[c] = one.lo[c] + 2;  // three layers each way
  EXPECT_FALSE(CutSearch(fine, thin).choose(VoxelSet(fine, one)).has_value());
}

}  // namespace
}  // namespace hfts::preprocess
