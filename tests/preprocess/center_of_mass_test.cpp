#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "preprocess/center_of_mass.h"
#include "test_meshes.h"

namespace hfts::preprocess {
namespace {

constexpr double kRadius = 0.04, kHeight = 0.1, kWall = 0.005, kFloor = 0.006;

/// Area of the 64-gon test::cup's rings approximate a circle of radius r with.
double ringArea(double r) {
  return 32.0 * r * r * std::sin(2.0 * M_PI / 64.0);
}

/// The cup's exact volume and centroid: an outer prism minus the cavity.
SolidProperties exactCup() {
  const double outer = ringArea(kRadius) * kHeight;
  const double cavity = ringArea(kRadius - kWall) * (kHeight - kFloor);
  SolidProperties s;
  s.volume = outer - cavity;
  s.centroid.z() = (outer * kHeight / 2 - cavity * (kHeight + kFloor) / 2) / s.volume;
  return s;
}

TriangleMesh withoutTriangles(const TriangleMesh& mesh, const std::vector<Eigen::Index>& drop) {
  TriangleMesh out{mesh.vertices, Triangles(mesh.triangles.rows() - drop.size(), 3)};
  Eigen::Index row = 0;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    if (std::find(drop.begin(), drop.end(), t) == drop.end())
      out.triangles.row(row++) = mesh.triangles.row(t);
  return out;
}

/// A copy of vertex v at the same place, taken by every other triangle
/// around v: an unwelded vertex, as a loader that welds nothing leaves it.
TriangleMesh unwelded(TriangleMesh mesh, std::uint32_t v) {
  const auto copy = static_cast<std::uint32_t>(mesh.vertices.rows());
  mesh.vertices.conservativeResize(copy + 1, 3);
  mesh.vertices.row(copy) = mesh.vertices.row(v);
  bool take = false;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k)
      if (mesh.triangles(t, k) == v && (take = !take)) mesh.triangles(t, k) = copy;
  return mesh;
}

TriangleMesh withTriangle(TriangleMesh mesh, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  mesh.triangles.conservativeResize(mesh.triangles.rows() + 1, 3);
  mesh.triangles.row(mesh.triangles.rows() - 1) << a, b, c;
  return mesh;
}

std::uint32_t withVertex(TriangleMesh& mesh, const Eigen::Vector3d& p) {
  mesh.vertices.conservativeResize(mesh.vertices.rows() + 1, 3);
  mesh.vertices.row(mesh.vertices.rows() - 1) = p.transpose();
  return static_cast<std::uint32_t>(mesh.vertices.rows() - 1);
}

/// Triangle t split at the middle of its first edge (a, b) into two, the
/// crack closed by the zero-area triangle (a, b, m): a T-junction as scans
/// hold them. The loader drops such triangles (sanitizeMesh), which leaves
/// a crack of three boundary edges.
TriangleMesh withTJunction(TriangleMesh mesh, Eigen::Index t) {
  const std::uint32_t a = mesh.triangles(t, 0), b = mesh.triangles(t, 1), c = mesh.triangles(t, 2);
  const std::uint32_t m =
      withVertex(mesh, 0.5 * (mesh.vertices.row(a) + mesh.vertices.row(b)).transpose());
  mesh.triangles.row(t) << a, m, c;
  return withTriangle(withTriangle(mesh, m, b, c), a, b, m);
}

double distanceToExact(const CenterOfMass& com) {
  return (com.point - exactCup().centroid).norm();
}

CenterOfMass centerOfMassOf(const TriangleMesh& mesh) {
  return centerOfMass(mesh, analyzeTopology(mesh).closed(), ConvexHull(mesh.vertices, "cup"));
}

TEST(CenterOfMass, OfAClosedMeshIsItsExactVolumeCentroid) {
  const TriangleMesh cup = test::cup();
  ASSERT_TRUE(analyzeTopology(cup).closed());
  const CenterOfMass com = centerOfMassOf(cup);
  EXPECT_EQ(com.method, db::CenterOfMassMethod::kClosedMesh);
  EXPECT_NEAR(com.volume, exactCup().volume, 1e-15);
  EXPECT_LT(distanceToExact(com), 1e-12);
  // The hull centroid counts the cavity as solid: 7.7 mm too high.
  EXPECT_GT((ConvexHull(cup.vertices, "cup").centroid() - com.point).norm(), 0.007);
}

TEST(CenterOfMass, ACupWithTrianglesRemovedKeepsItsExactCentroid) {
  const TriangleMesh cup = test::cup();
  const Eigen::Index n = cup.triangles.rows();
  for (const std::vector<Eigen::Index>& drop : {std::vector<Eigen::Index>{n / 2},
                                                {n / 3, 2 * n / 3},
                                                {7, n / 2 + 1, n - 5},
                                                {n / 2, n / 2 + 1, n / 2 + 2}}) {
    const TriangleMesh open = withoutTriangles(cup, drop);
    ASSERT_FALSE(analyzeTopology(open).closed());
    const CenterOfMass com = centerOfMassOf(open);
    EXPECT_EQ(com.method, db::CenterOfMassMethod::kRepairedMesh) << drop.size() << " removed";
    EXPECT_LT(distanceToExact(com), 1e-9) << drop.size() << " removed";
    EXPECT_NEAR(com.volume, exactCup().volume, 1e-12);
  }
}

TEST(CenterOfMass, UnweldedVerticesDroppedSliversAndFlapsDoNotMoveIt) {
  TriangleMesh damaged = unwelded(unwelded(test::cup(), 40), 200);
  damaged = withTJunction(withTJunction(damaged, 100), 1500);
  // A flap on an edge of triangle 900 makes that edge non-manifold.
  const std::uint32_t a = damaged.triangles(900, 0), b = damaged.triangles(900, 1);
  const Eigen::Vector3d middle = 0.5 * (damaged.vertices.row(a) + damaged.vertices.row(b));
  const std::uint32_t tip = withVertex(damaged, middle * 1.02);
  damaged = withTriangle(damaged, a, b, tip);
  sanitizeMesh(damaged, "damaged cup");  // the loader drops the two slivers
  const MeshTopology topology = analyzeTopology(damaged);
  ASSERT_GT(topology.boundary_edges, 0u);
  ASSERT_EQ(topology.non_manifold_edges, 1u);

  const CenterOfMass com = centerOfMassOf(damaged);
  EXPECT_EQ(com.method, db::CenterOfMassMethod::kRepairedMesh);
  EXPECT_LT(distanceToExact(com), 1e-9);
  EXPECT_NEAR(com.volume, exactCup().volume, 1e-12);
}

TEST(CenterOfMass, ACupScannedWithoutItsBottomIsClosedByAFlatCap) {
  const TriangleMesh cup = test::cup();
  std::vector<Eigen::Index> bottom;
  for (Eigen::Index t = 0; t < cup.triangles.rows(); ++t)
    if ((cup.vertices(cup.triangles(t, 0), 2) == 0.0) &&
        (cup.vertices(cup.triangles(t, 1), 2) == 0.0) &&
        (cup.vertices(cup.triangles(t, 2), 2) == 0.0))
      bottom.push_back(t);
  const TriangleMesh bottomless = withoutTriangles(cup, bottom);
  const BoundaryCaps caps = boundaryCaps(bottomless);
  EXPECT_EQ(caps.parts, 1u);
  EXPECT_NEAR(caps.area, ringArea(kRadius), 1e-12);
  const CenterOfMass com = centerOfMassOf(bottomless);
  EXPECT_EQ(com.method, db::CenterOfMassMethod::kRepairedMesh);
  EXPECT_LT(distanceToExact(com), 1e-9);
}

TEST(CenterOfMass, AWindingMistakeIsUndoneByTheCaps) {
  TriangleMesh mesh = test::cup();
  mesh.triangles.row(321).reverseInPlace();
  ASSERT_EQ(analyzeTopology(mesh).inconsistent_edges, 3u);
  const CenterOfMass com = centerOfMassOf(mesh);
  EXPECT_EQ(com.method, db::CenterOfMassMethod::kRepairedMesh);
  EXPECT_LT(distanceToExact(com), 1e-9);
}

TEST(CenterOfMass, FlatHolesOfAnySizeAreFilledByTheirPlanes) {
  // A cube without two opposite faces is a square tube; its two square
  // holes are flat, so the caps are exactly the missing faces.
  const TriangleMesh tube = withoutTriangles(test::cube(0.1, {0.2, 0, 0}), {0, 1, 2, 3});
  const BoundaryCaps caps = boundaryCaps(tube);
  EXPECT_EQ(caps.parts, 2u);
  EXPECT_NEAR(caps.area, 0.02, 1e-12);
  EXPECT_NEAR(caps.ambiguity, 0.0, 1e-18);
  const CenterOfMass com = centerOfMass(tube, false, ConvexHull(tube.vertices, "tube"));
  EXPECT_EQ(com.method, db::CenterOfMassMethod::kRepairedMesh);
  EXPECT_NEAR(com.volume, 1e-3, 1e-15);
  EXPECT_TRUE(com.point.isApprox(Eigen::Vector3d(0.2, 0, 0), 1e-12));
}

TEST(CenterOfMass, AWarpedSheetFallsBackToTheHullCentroid) {
  // Two faces of a cube meeting at an edge: a folded sheet whose boundary
  // is a skew hexagon. Any cap would invent the solid.
  const TriangleMesh sheet =
      withoutTriangles(test::cube(0.1, {0.2, 0, 0}), {2, 3, 6, 7, 8, 9, 10, 11});
  ASSERT_EQ(sheet.triangles.rows(), 4);
  EXPECT_EQ(boundaryCaps(sheet).parts, 1u);
  const ConvexHull hull(sheet.vertices, "folded sheet");
  const CenterOfMass com = centerOfMass(sheet, false, hull);
  EXPECT_GT(com.cap_ambiguity, kMaxCapAmbiguity);
  EXPECT_EQ(com.method, db::CenterOfMassMethod::kConvexHull);
  EXPECT_EQ(com.volume, 0.0);
  EXPECT_TRUE(com.point.isApprox(hull.centroid(), 1e-12));
}

TEST(BoundaryCaps, OfAClosedMeshAreEmpty) {
  const BoundaryCaps caps = boundaryCaps(test::cup());
  EXPECT_EQ(caps.parts, 0u);
  EXPECT_EQ(caps.caps.triangles.rows(), 0);
  EXPECT_EQ(caps.area, 0.0);
}

TEST(SolidProperties, InvertedWindingGivesThePositiveVolume) {
  const SolidProperties s = solidProperties(test::flipped(test::cube(0.2)));
  EXPECT_NEAR(s.volume, 0.008, 1e-12);
  EXPECT_LT(s.centroid.norm(), 1e-12);
}

}  // namespace
}  // namespace hfts::preprocess
