#include <gtest/gtest.h>

#include <cmath>

#include "preprocess/contact_filters.h"
#include "preprocess/fingertip_scale.h"
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

/// Filters over `mesh`: its hull and surface, built once.
struct Geometry {
  explicit Geometry(const TriangleMesh& mesh) : hull(mesh.vertices, "test mesh"), surface(mesh) {}
  ConvexHull hull;
  db::TriangleBvh surface;
  operator FilterGeometry() const { return {hull, surface}; }
};

/// The default parameters resolved at the default sampling density.
db::BuildParameters resolvedDefaults() {
  db::BuildParameters params;
  return resolveFilterScales(params, params.sample_density);
}

TEST(ContactFilters, CurvatureFilterRemovesCubeEdgesAndKeepsFaces) {
  const TriangleMesh mesh = test::cube(0.1);
  const SurfaceSamples s = sampleVisibleSurface(mesh, SamplingOptions{});
  ContactSet c = estimateNormals(s.positions, s.normals, 0.01);
  db::BuildParameters params;
  params.filters = {"curvature"};
  params.patch_radius = 0.01;
  const std::size_t before = c.size();
  const auto reports = applyFilters(c, params, Geometry(mesh));
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
  const Geometry cube(test::cube(0.1));
  ContactSet c = syntheticContacts({{0, 0, 0.05}, {0, 0, 0.045}, {0, 0, 0.0}, {0.049, 0, 0}});
  db::BuildParameters params;
  params.filters = {"concavity"};
  params.max_hull_distance = 0.01;
  const auto reports = applyFilters(c, params, cube);
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
  params.patch_radius = 0.01;
  params.min_neighbours = 10;
  const Geometry bigCube(test::cube(2.0));
  const auto reports = applyFilters(c, params, bigCube);
  EXPECT_EQ(reports[0].removed, 1u);
  EXPECT_EQ(c.size(), 30u);
  params.min_neighbours = 30;  // nobody has 30 others
  EXPECT_EQ(applyFilters(c, params, bigCube)[0].removed, 30u);
}

TEST(ContactFilters, ChainRunsInTheConfiguredOrderAndReportsEachFilter) {
  ContactSet c = syntheticContacts({{0, 0, 0}, {0, 0, 0.001}});
  c.curvature(0) = 0.2;
  db::BuildParameters params;
  params.filters = {"neighbours", "curvature"};
  params.patch_radius = 0.01;
  params.min_neighbours = 1;
  const auto reports = applyFilters(c, params, Geometry(test::cube(0.1)));
  ASSERT_EQ(reports.size(), 2u);
  EXPECT_EQ(reports[0].name, "neighbours");
  EXPECT_EQ(reports[0].removed, 0u);
  EXPECT_EQ(reports[1].name, "curvature");
  EXPECT_EQ(reports[1].removed, 1u);
}

TEST(ContactFilters, ClearanceRemovesTheBandBesideACreaseThatAPadCannotReach) {
  // Two boxes make an L: the top of the lower one meets the side of the
  // upper one in a concave crease along y at x = 0.05, z = 0.05.
  const Geometry l(test::merged(test::cube(0.1, {0.1, 0, 0}), test::cube(0.1, {0, 0, 0.1})));
  db::BuildParameters params = resolvedDefaults();
  params.filters = {"clearance"};
  const double pad = params.pad_radius;
  std::vector<Eigen::Vector3d> onTop;
  for (const double t : {0.2, 0.5, 0.9, 0.94, 0.96, 1.0, 1.5, 3.0})
    onTop.emplace_back(0.05 + t * pad, 0.01, 0.05);  // t pad radii from the crease
  ContactSet c = syntheticContacts(onTop);
  applyFilters(c, params, l);
  ASSERT_EQ(c.size(), 4u);
  EXPECT_NEAR(c.positions(0, 0), 0.05 + 0.96 * pad, 1e-12);
}

TEST(ContactFilters, ClearanceKeepsEveryContactOfAConvexObject) {
  const TriangleMesh ball = test::revolved({{0, -0.03},
                                            {0.015, -0.026},
                                            {0.026, -0.015},
                                            {0.03, 0},
                                            {0.026, 0.015},
                                            {0.015, 0.026},
                                            {0, 0.03}},
                                           24);
  const SurfaceSamples s = sampleVisibleSurface(ball, SamplingOptions{});
  db::BuildParameters params = resolvedDefaults();
  params.filters = {"clearance"};
  params.pad_radius = 0.014;
  ContactSet c = estimateNormals(s.positions, s.normals, params.patch_radius);
  EXPECT_EQ(applyFilters(c, params, Geometry(ball))[0].removed, 0u);
}

/// A cylinder of radius r and length 13 cm lying along z: a marker pen.
TriangleMesh rod(double r) {
  std::vector<Eigen::Vector2d> profile = {{0, 0}, {r, 0}};
  for (double z = 0.004; z < 0.13; z += 0.004) profile.emplace_back(r, z);
  profile.insert(profile.end(), {{r, 0.13}, {0, 0.13}});
  return test::revolved(profile, 48);
}

/// The contacts of `mesh` before filtering, as the database builder
/// estimates them.
ContactSet unfiltered(const TriangleMesh& mesh, const SurfaceSamples& s, double patchRadius) {
  const SurfaceSamples support = supportSamples(mesh, s, patchRadius, SamplingOptions{});
  return estimateNormals(s.positions, s.normals, {support.positions, support.normals}, patchRadius);
}

/// Of the samples of `rod` farther than 2 cm from its ends, the share the
/// filters of `params` keep.
double sideKept(const TriangleMesh& rod, const db::BuildParameters& params) {
  const SurfaceSamples s = sampleVisibleSurface(rod, SamplingOptions{});
  ContactSet c = unfiltered(rod, s, params.patch_radius);
  const auto onSide = [](const Vertices& p) {
    std::size_t n = 0;
    for (Eigen::Index i = 0; i < p.rows(); ++i) n += std::abs(p(i, 2) - 0.065) < 0.045;
    return n;
  };
  const std::size_t before = onSide(c.positions);
  applyFilters(c, params, Geometry(rod));
  return static_cast<double>(onSide(c.positions)) / static_cast<double>(before);
}

TEST(ContactFilters, AMarkerPenKeepsItsSideForTheFingertipsOfEveryBundledHand) {
  const TriangleMesh marker = rod(0.0085);
  for (const double pad : {0.008, 0.012, 0.014}) {  // Panda, Allegro, SDH
    db::BuildParameters params;
    params.pad_radius = pad;
    EXPECT_GT(sideKept(marker, resolveFilterScales(params, params.sample_density)), 0.9)
        << "pad " << pad;
  }
  // The fixed scales this replaced kept almost nothing of it.
  db::BuildParameters fixed;
  fixed.patch_radius = 0.01;
  fixed.max_hull_distance = 0.01;
  fixed.min_neighbours = 10;
  fixed.filters = {"curvature", "concavity", "neighbours"};
  EXPECT_LT(sideKept(marker, fixed), 0.05);
}

TEST(ContactFilters, ABoxLosesItsEdgesAndKeepsItsFaces) {
  const TriangleMesh mesh = test::cube(0.05);
  const SurfaceSamples s = sampleVisibleSurface(mesh, SamplingOptions{});
  const db::BuildParameters params = resolvedDefaults();
  ContactSet c = unfiltered(mesh, s, params.patch_radius);
  applyFilters(c, params, Geometry(mesh));
  // Nothing within 1.2 mm of an edge (a sharp edge's surface variation
  // falls below 0.03 from about 0.7 patch radii, 2.8 mm, on) ...
  std::size_t inner = 0;
  for (Eigen::Index i = 0; i < c.positions.rows(); ++i) {
    const double d = edgeDistance(c.positions.row(i).transpose(), 0.025);
    EXPECT_GT(d, 0.15 * params.pad_radius) << "kept at " << c.positions.row(i);
    inner += d > params.pad_radius;
  }
  // ... and a pad radius from every edge nothing is lost but the odd
  // sample with fewer than min_neighbours (3) others in its patch.
  std::size_t innerSamples = 0;
  for (Eigen::Index i = 0; i < s.positions.rows(); ++i)
    innerSamples += edgeDistance(s.positions.row(i).transpose(), 0.025) > params.pad_radius;
  EXPECT_GE(static_cast<double>(inner), 0.99 * static_cast<double>(innerSamples));
}

TEST(ContactFilters, UnresolvedScalesAreRejected) {
  ContactSet c = syntheticContacts({{0, 0, 0.05}});
  const Geometry cube(test::cube(0.1));
  for (const char* filter : {"curvature", "clearance", "neighbours"}) {
    db::BuildParameters params;  // scales 0: resolveFilterScales was not called
    params.filters = {filter};
    if (params.filters[0] == "clearance") params.pad_radius = 0.0;
    EXPECT_THROW(applyFilters(c, params, cube), std::invalid_argument) << filter;
  }
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
  EXPECT_EQ(knownFilters(),
            (std::vector<std::string>{"curvature", "concavity", "clearance", "neighbours"}));
  EXPECT_EQ(db::BuildParameters{}.filters, knownFilters());
}

}  // namespace
}  // namespace hfts::preprocess
