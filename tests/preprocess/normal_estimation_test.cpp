#include <gtest/gtest.h>

#include "hfts_db/object_database.h"
#include "preprocess/contact_set.h"
#include "preprocess/surface_sampler.h"
#include "test_meshes.h"

namespace hfts::preprocess {
namespace {

TEST(NormalEstimation, FaceCentresOfACubeGetTheFaceNormalAndNoCurvature) {
  const SurfaceSamples s = sampleVisibleSurface(test::cube(0.1), SamplingOptions{});
  const ContactSet c = estimateNormals(s.positions, s.normals, 0.01);
  int checked = 0;
  for (Eigen::Index i = 0; i < c.positions.rows(); ++i) {
    const Eigen::Vector3d p = c.positions.row(i).transpose();
    // Farther than the patch radius from every edge: a flat patch.
    Eigen::Vector3d q = p.cwiseAbs();
    std::sort(q.data(), q.data() + 3);
    if (q[1] > 0.05 - 0.012) continue;
    EXPECT_NEAR(c.normals.row(i).dot(s.normals.row(i)), 1.0, 1e-5);
    EXPECT_LT(c.curvature(i), 1e-4);
    ++checked;
  }
  EXPECT_GT(checked, 1000);
}

TEST(NormalEstimation, EdgesOfACubeHaveHighCurvature) {
  const SurfaceSamples s = sampleVisibleSurface(test::cube(0.1), SamplingOptions{});
  const ContactSet c = estimateNormals(s.positions, s.normals, 0.01);
  int checked = 0;
  for (Eigen::Index i = 0; i < c.positions.rows(); ++i) {
    Eigen::Vector3d q = c.positions.row(i).transpose().cwiseAbs();
    std::sort(q.data(), q.data() + 3);
    if (q[1] < 0.05 - 0.001) continue;  // within 1 mm of an edge
    EXPECT_GT(c.curvature(i), db::BuildParameters{}.max_curvature);
    ++checked;
  }
  EXPECT_GT(checked, 10);
}

TEST(NormalEstimation, ThinWallSidesDoNotMix) {
  // Two parallel sheets 2 mm apart, seen from opposite sides: each side's
  // patch must stay flat although the other lies within the radius.
  const TriangleMesh top = test::square(0.1, 0.001);
  const TriangleMesh bottom = test::flipped(test::square(0.1, -0.001));
  Vertices positions(200, 3), sides(200, 3);
  for (int i = 0; i < 100; ++i) {
    const double x = 0.002 * (i % 10), y = 0.002 * (i / 10);
    positions.row(i) << x, y, 0.001;
    sides.row(i) << 0, 0, 1;
    positions.row(100 + i) << x, y, -0.001;
    sides.row(100 + i) << 0, 0, -1;
  }
  const ContactSet c = estimateNormals(positions, sides, 0.01);
  for (Eigen::Index i = 0; i < 200; ++i) {
    EXPECT_LT(c.curvature(i), 1e-6);
    EXPECT_NEAR(c.normals.row(i).dot(sides.row(i)), 1.0, 1e-6);
  }
}

TEST(NormalEstimation, IsolatedPointsKeepTheirSideNormalWithMaximalCurvature) {
  Vertices positions(2, 3), sides(2, 3);
  positions << 0, 0, 0, 1, 1, 1;
  sides << 0, 0, 1, 1, 0, 0;
  const ContactSet c = estimateNormals(positions, sides, 0.01);
  EXPECT_EQ(c.normals, sides);
  EXPECT_DOUBLE_EQ(c.curvature(0), 1.0 / 3.0);
}

TEST(ContactSet, KeepRetainsMaskedRowsInOrder) {
  ContactSet c;
  c.positions = Vertices::Random(4, 3);
  c.normals = Vertices::Random(4, 3);
  c.curvature = Eigen::VectorXd::LinSpaced(4, 0, 3);
  const Vertices before = c.positions;
  c.keep({true, false, false, true});
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c.positions.row(1), before.row(3));
  EXPECT_DOUBLE_EQ(c.curvature(1), 3.0);
  EXPECT_THROW(c.keep({true}), std::logic_error);
}

}  // namespace
}  // namespace hfts::preprocess
