#include <gtest/gtest.h>

#include "preprocess/contact_filters.h"
#include "preprocess/surface_sampler.h"
#include "test_meshes.h"

namespace hfts::preprocess {
namespace {

/// Distance of a point on the cube's surface to the nearest cube edge.
double edgeDistance(const Eigen::Vector3d& p, double half) {
  Eigen::Vector3d q = p.cwiseAbs();
  std::sort(q.data(), q.data() + 3);
  return half - q[1];
}

TEST(ContactFilters, CurvatureFilterRemovesCubeEdgesAndKeepsFaces) {
  const TriangleMesh mesh = test::cube(0.1);
  const SurfaceSamples s = sampleVisibleSurface(mesh, SamplingOptions{});
  ContactSet c = estimateNormals(s.positions, s.normals, 0.01);
  db::BuildParameters params;
  params.filters = {"curvature"};
  const std::size_t before = c.size();
  const auto reports = applyFilters(c, params, ConvexHull(mesh.vertices, "cube"));
  ASSERT_EQ(reports.size(), 1u);
  EXPECT_EQ(reports[0].name, "curvature");
  EXPECT_EQ(reports[0].removed, before - c.size());
  EXPECT_GT(reports[0].removed, 0u);
  int perFace[6] = {};
  for (Eigen::Index i = 0; i < c.positions.rows(); ++i) {
    const Eigen::Vector3d p = c.positions.row(i).transpose();
    EXPECT_GT(edgeDistance(p, 0.05), 0.002) << "edge point kept at " << p.transpose();
    Eigen::Index axis = 0;
    p.cwiseAbs().maxCoeff(&axis);
    ++perFace[2 * axis + (p[axis] > 0)];
  }
  for (int count : perFace) EXPECT_GT(count, 500);
  // Everything farther than the patch radius from an edge survives.
  for (Eigen::Index i = 0; i < s.positions.rows(); ++i) {
    if (edgeDistance(s.positions.row(i).transpose(), 0.05) < 0.011) continue;
    bool kept = false;
    for (Eigen::Index j = 0; j < c.positions.rows() && !kept; ++j)
      kept = c.positions.row(j) == s.positions.row(i);
    EXPECT_TRUE(kept);
    if (!kept) break;
  }
}

ContactSet syntheticContacts(const std::vector<Eigen::Vector3d>& points) {
  ContactSet c;
  c.positions.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    c.positions.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
  c.normals = Vertices::Zero(c.positions.rows(), 3);
  c.normals.col(2).setOnes();
  c.curvature = Eigen::VectorXd::Zero(c.positions.rows());
  return c;
}

TEST(ContactFilters, ConcavityFilterRemovesContactsDeepBelowTheHull) {
  const ConvexHull hull(test::cube(0.1).vertices, "cube");
  ContactSet c = syntheticContacts({{0, 0, 0.05}, {0, 0, 0.045}, {0, 0, 0.0}, {0.049, 0, 0}});
  db::BuildParameters params;
  params.filters = {"concavity"};
  params.max_hull_distance = 0.01;
  const auto reports = applyFilters(c, params, hull);
  EXPECT_EQ(reports[0].removed, 1u);  // only the centre is 5 cm deep
  ASSERT_EQ(c.size(), 3u);
  EXPECT_DOUBLE_EQ(c.positions(2, 0), 0.049);
}

TEST(ContactFilters, NeighboursFilterRemovesIsolatedContacts) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 30; ++i) points.emplace_back(0.001 * (i % 6), 0.001 * (i / 6), 0.0);
  points.emplace_back(0.5, 0.5, 0.5);  // alone
  ContactSet c = syntheticContacts(points);
  db::BuildParameters params;
  params.filters = {"neighbours"};
  params.min_neighbours = 10;
  const ConvexHull hull(test::cube(2.0).vertices, "big cube");
  const auto reports = applyFilters(c, params, hull);
  EXPECT_EQ(reports[0].removed, 1u);
  EXPECT_EQ(c.size(), 30u);
  params.min_neighbours = 30;  // nobody has 30 others
  EXPECT_EQ(applyFilters(c, params, hull)[0].removed, 30u);
}

TEST(ContactFilters, ChainRunsInTheConfiguredOrderAndReportsEachFilter) {
  ContactSet c = syntheticContacts({{0, 0, 0}, {0, 0, 0.001}});
  c.curvature(0) = 0.2;
  db::BuildParameters params;
  params.filters = {"neighbours", "curvature"};
  params.min_neighbours = 1;
  const auto reports = applyFilters(c, params, ConvexHull(test::cube(0.1).vertices, "cube"));
  ASSERT_EQ(reports.size(), 2u);
  EXPECT_EQ(reports[0].name, "neighbours");
  EXPECT_EQ(reports[0].removed, 0u);
  EXPECT_EQ(reports[1].name, "curvature");
  EXPECT_EQ(reports[1].removed, 1u);
}

TEST(ContactFilters, UnknownOrRepeatedFiltersAreRejectedByName) {
  try {
    checkFilterNames({"curvature", "smoothness"});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'smoothness'"), std::string::npos);
  }
  EXPECT_THROW(checkFilterNames({"curvature", "curvature"}), std::invalid_argument);
  EXPECT_NO_THROW(checkFilterNames({}));
  EXPECT_EQ(knownFilters().size(), 3u);
}

}  // namespace
}  // namespace hfts::preprocess
