#include <gtest/gtest.h>

#include "preprocess/surface_sampler.h"
#include "test_meshes.h"

namespace hfts::preprocess {
namespace {

constexpr double kSize = 0.1;

/// Index 0..5 of the cube face (-x, +x, -y, +y, -z, +z) a point lies on.
int faceOf(const Eigen::Vector3d& p) {
  Eigen::Index axis = 0;
  p.cwiseAbs().maxCoeff(&axis);
  return static_cast<int>(2 * axis + (p[axis] > 0 ? 1 : 0));
}

TEST(SurfaceSampler, CubeIsSampledOnAllSixFacesWithOutwardNormals) {
  const SurfaceSamples s = sampleVisibleSurface(test::cube(kSize), SamplingOptions{});
  ASSERT_GT(s.positions.rows(), 0);
  int perFace[6] = {0, 0, 0, 0, 0, 0};
  for (Eigen::Index i = 0; i < s.positions.rows(); ++i) {
    const Eigen::Vector3d p = s.positions.row(i).transpose();
    const Eigen::Vector3d n = s.normals.row(i).transpose();
    EXPECT_NEAR(p.cwiseAbs().maxCoeff(), kSize / 2, 1e-9);  // on the surface
    const int face = faceOf(p);
    Eigen::Vector3d outward = Eigen::Vector3d::Zero();
    outward[face / 2] = face % 2 ? 1.0 : -1.0;
    EXPECT_NEAR(n.dot(outward), 1.0, 1e-9);
    ++perFace[face];
  }
  // Area-uniform: each face holds about a sixth of the samples.
  const double expected = static_cast<double>(s.positions.rows()) / 6.0;
  for (int count : perFace) EXPECT_NEAR(count, expected, 0.05 * expected);
}

TEST(SurfaceSampler, SampleCountFollowsDensityAndCap) {
  SamplingOptions options;
  options.density = 50000.0;
  const SurfaceSamples s = sampleVisibleSurface(test::cube(kSize), options);
  EXPECT_EQ(s.candidates, 3000u);  // 0.06 m^2 * 50000 / m^2
  EXPECT_EQ(s.positions.rows(), 3000);
  options.max_samples = 500;
  EXPECT_EQ(sampleVisibleSurface(test::cube(kSize), options).positions.rows(), 500);
}

TEST(SurfaceSampler, InternalFaceYieldsNoSamples) {
  // A square floating inside the cube is seen from nowhere.
  const TriangleMesh mesh = test::merged(test::cube(kSize), test::square(0.8 * kSize, 0.0));
  const SurfaceSamples s = sampleVisibleSurface(mesh, SamplingOptions{});
  ASSERT_GT(s.positions.rows(), 0);
  for (Eigen::Index i = 0; i < s.positions.rows(); ++i)
    EXPECT_NEAR(s.positions.row(i).cwiseAbs().maxCoeff(), kSize / 2, 1e-9);
  EXPECT_LT(s.positions.rows(), static_cast<Eigen::Index>(s.candidates));
}

TEST(SurfaceSampler, ClosedCavityYieldsNoSamples) {
  // A hollow cube: the cavity's walls (inward winding) are invisible.
  const TriangleMesh mesh = test::merged(test::cube(kSize), test::flipped(test::cube(0.5 * kSize)));
  const SurfaceSamples s = sampleVisibleSurface(mesh, SamplingOptions{});
  ASSERT_GT(s.positions.rows(), 0);
  for (Eigen::Index i = 0; i < s.positions.rows(); ++i)
    EXPECT_NEAR(s.positions.row(i).cwiseAbs().maxCoeff(), kSize / 2, 1e-9);
}

TEST(SurfaceSampler, OpenSheetIsSampledOnBothSides) {
  const SurfaceSamples s = sampleVisibleSurface(test::square(kSize, 0.0), SamplingOptions{});
  int up = 0, down = 0;
  for (Eigen::Index i = 0; i < s.normals.rows(); ++i) (s.normals(i, 2) > 0 ? up : down) += 1;
  EXPECT_EQ(up, static_cast<int>(s.candidates));
  EXPECT_EQ(down, static_cast<int>(s.candidates));
}

TEST(SurfaceSampler, InvertedWindingStillGivesOutwardNormals) {
  const SurfaceSamples s =
      sampleVisibleSurface(test::flipped(test::cube(kSize)), SamplingOptions{});
  for (Eigen::Index i = 0; i < s.positions.rows(); ++i)
    EXPECT_GT(s.normals.row(i).dot(s.positions.row(i)), 0.0);
}

TEST(SurfaceSampler, IsDeterministicPerSeed) {
  SamplingOptions options;
  const SurfaceSamples a = sampleVisibleSurface(test::cube(kSize), options);
  const SurfaceSamples b = sampleVisibleSurface(test::cube(kSize), options);
  EXPECT_EQ(a.positions, b.positions);
  options.seed = 2;
  const SurfaceSamples c = sampleVisibleSurface(test::cube(kSize), options);
  EXPECT_NE(a.positions, c.positions);
}

TEST(SurfaceSampler, RejectsBadOptions) {
  SamplingOptions options;
  options.density = 0.0;
  EXPECT_THROW(sampleVisibleSurface(test::cube(kSize), options), std::invalid_argument);
  options = SamplingOptions{};
  options.viewpoints = 2;
  EXPECT_THROW(sampleVisibleSurface(test::cube(kSize), options), std::invalid_argument);
}

TEST(FibonacciSphere, GivesSpreadUnitDirections) {
  const Vertices d = fibonacciSphere(64);
  ASSERT_EQ(d.rows(), 64);
  for (Eigen::Index i = 0; i < d.rows(); ++i) EXPECT_NEAR(d.row(i).norm(), 1.0, 1e-12);
  EXPECT_LT(d.colwise().mean().norm(), 0.05);
}

}  // namespace
}  // namespace hfts::preprocess
