#include "solid_lattice.h"

#include <gtest/gtest.h>

#include <random>

#include "test_meshes.h"

namespace hfts::preprocess {
namespace {

TEST(SolidLattice, StartsHalfAVoxelBeforeTheBoundingBox) {
  // 16 voxels of 6.25 mm across the 10 cm cube, and one more on each side.
  const SolidLattice lattice(test::cube(0.1), 16);
  EXPECT_DOUBLE_EQ(lattice.spacing(), 0.00625);
  EXPECT_DOUBLE_EQ(lattice.centre(0, 0), -0.05 - 0.003125);
  EXPECT_DOUBLE_EQ(lattice.face(0, 1), -0.05);
  const VoxelBox whole = lattice.whole();
  for (int axis = 0; axis < 3; ++axis) EXPECT_EQ(whole.size(axis), 18);
}

TEST(SolidLattice, RunsAreTheVoxelsWhoseCentresAreInside) {
  const SolidLattice lattice(test::cube(0.1), 16);
  std::vector<LevelRun> runs;
  lattice.runs(8, 8, 0, 17, runs);
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].first, 1);
  EXPECT_EQ(runs[0].last, 16);
  lattice.runs(8, 8, 5, 9, runs);  // within levels 5..9
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].first, 5);
  EXPECT_EQ(runs[0].last, 9);
  lattice.runs(0, 8, 0, 17, runs);  // beside the cube
  EXPECT_TRUE(runs.empty());
}

TEST(SolidLattice, VolumeInABoxIsExactAlongTheLinesAndByTheirSquaresAcross) {
  const SolidLattice lattice(test::cube(0.1), 16);
  EXPECT_NEAR(lattice.volumeIn({-1, -1, -1}, {1, 1, 1}), 0.001, 1e-15);
  EXPECT_NEAR(lattice.volumeIn({-1, -1, -1}, {0, 1, 1}), 0.0005, 1e-15);  // 0 is a voxel face
  EXPECT_NEAR(lattice.volumeIn({-1, -1, -0.013}, {1, 1, 1}), 0.1 * 0.1 * 0.063, 1e-15);
}

TEST(SolidLattice, ContainsAgreesWithTheWindingNumberOfTheMug) {
  const TriangleMesh mug = loadMesh(test::bundledMeshDir() / "mug.ply").mesh;
  const SolidLattice lattice(mug, 64);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> x(-0.045, 0.08), y(-0.045, 0.045), z(-0.005, 0.105);
  int inside = 0;
  for (int n = 0; n < 600; ++n) {
    const Eigen::Vector3d p(x(rng), y(rng), z(rng));
    const bool in = std::abs(test::windingNumber(mug, p)) > 0.5;
    EXPECT_EQ(lattice.contains(p), in) << p.transpose();
    inside += in ? 1 : 0;
  }
  EXPECT_GT(inside, 40);
}

}  // namespace
}  // namespace hfts::preprocess
