#include "physics/object_body.h"

#include <gtest/gtest.h>

#include "bundled_objects.h"
#include "core/invalid_argument.h"
#include "panda_cube.h"
#include "test_meshes.h"

namespace hfts::physics {
namespace {

/// A box of edges (a, b, c) centred at `center`, as closed mesh arrays.
std::pair<db::Points3, db::Faces3> box(const Eigen::Vector3d& edges,
                                       const Eigen::Vector3d& center) {
  TriangleMesh mesh = test::cube(1.0);
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v)
    mesh.vertices.row(v) =
        (mesh.vertices.row(v).transpose().cwiseProduct(edges) + center).transpose();
  return {mesh.vertices, mesh.triangles};
}

TEST(ObjectBody, ABoxHasItsAnalyticMassCentreAndInertia) {
  const Eigen::Vector3d edges(0.1, 0.04, 0.02);
  const Eigen::Vector3d center(0.3, -0.2, 1.5);  // far from the origin: no cancellation
  const auto [vertices, faces] = box(edges, center);
  const double density = 700.0;
  const MassProperties p = solidMassProperties(vertices, faces, density);
  const double volume = edges.prod();
  const double mass = density * volume;
  EXPECT_NEAR(p.volume, volume, 1e-15);
  EXPECT_NEAR(p.mass, mass, 1e-12);
  EXPECT_TRUE(p.center_of_mass.isApprox(center, 1e-12));
  // m/12 (b^2 + c^2) and so on, no products of inertia.
  const Eigen::Vector3d sq = edges.cwiseAbs2();
  const Eigen::Vector3d expected =
      mass / 12.0 * Eigen::Vector3d(sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y());
  EXPECT_TRUE(p.inertia.diagonal().isApprox(expected, 1e-10)) << p.inertia;
  EXPECT_NEAR((p.inertia - Eigen::Matrix3d(p.inertia.diagonal().asDiagonal())).norm(), 0.0, 1e-15);
}

TEST(ObjectBody, ATurnedBoxHasItsInertiaTurned) {
  const auto [vertices, faces] = box(Eigen::Vector3d(0.1, 0.04, 0.02), Eigen::Vector3d::Zero());
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  const db::Points3 turned = vertices * r.transpose();
  const MassProperties a = solidMassProperties(vertices, faces, 1000);
  const MassProperties b = solidMassProperties(turned, faces, 1000);
  EXPECT_TRUE(b.inertia.isApprox(r * a.inertia * r.transpose(), 1e-10));
}

TEST(ObjectBody, AMeshThatBoundsNoVolumeIsRefusedNamingTheField) {
  auto [vertices, faces] = box(Eigen::Vector3d(0.1, 0.1, 0.1), Eigen::Vector3d::Zero());
  const auto fieldOf = [](auto&& call) {
    try {
      call();
    } catch (const InvalidArgument& e) {
      return e.field();
    }
    return std::string("no error");
  };
  EXPECT_EQ(fieldOf([&] { solidMassProperties(vertices, faces, 0.0); }), "density");
  EXPECT_EQ(fieldOf([&] { solidMassProperties(vertices, faces, std::nan("")); }), "density");
  const db::Faces3 inverted = faces.rowwise().reverse();
  EXPECT_EQ(fieldOf([&] { solidMassProperties(vertices, inverted, 1.0); }), "faces");
  db::Faces3 past = faces;
  past(0, 0) = 99;
  EXPECT_EQ(fieldOf([&] { solidMassProperties(vertices, past, 1.0); }), "faces");
}

TEST(ObjectBody, TheCubeCollidesAsItsOnePieceWithTheDatabasesMassAndCentre) {
  const db::ObjectDatabase& cube = test::smallCube();
  const std::vector<ConvexPiece> pieces = collisionPieces(cube);
  ASSERT_EQ(pieces.size(), 1u);  // a convex object is one piece: its hull
  EXPECT_EQ(pieces[0].vertices.rows(), cube.geometry.hull_vertices.rows());
  EXPECT_EQ(collisionShapeName(cube), "convex_parts");
  db::ObjectDatabase withoutParts = cube;
  withoutParts.geometry.convex_parts.clear();
  EXPECT_EQ(collisionShapeName(withoutParts), "hull");
  EXPECT_EQ(collisionPieces(withoutParts).size(), 1u);
  const MassProperties p = objectMassProperties(cube, 1000.0);
  EXPECT_NEAR(p.volume, cube.geometry.volume, 1e-12);
  EXPECT_TRUE(p.center_of_mass.isApprox(cube.geometry.center_of_mass, 1e-9));
  EXPECT_NEAR(p.mass, 1000 * 0.046 * 0.046 * 0.046, 1e-6);
}

TEST(ObjectBody, TheRequestedDensityWinsOverTheDefault) {
  EXPECT_EQ(objectDensity(test::smallCube(), std::nullopt), db::kDefaultDensity);
  EXPECT_EQ(objectDensity(test::smallCube(), 250.0), 250.0);
}

TEST(ObjectBody, TheMugCollidesAsItsConvexPartsAndAnOpenMeshWeighsAsThem) {
  const db::ObjectDatabase mug = test::bundledObject(test::bundledMeshDir() / "mug.ply");
  const std::vector<ConvexPiece> pieces = collisionPieces(mug);
  EXPECT_GT(pieces.size(), 10u);
  double volume = 0.0;
  for (const ConvexPiece& p : pieces)
    volume += solidMassProperties(p.vertices, p.faces, 1.0).volume;
  // The parts cover the solid within the decomposition's tolerance, where
  // its hull is four times its volume.
  EXPECT_GE(volume, mug.geometry.volume * (1 - 1e-9));
  EXPECT_LE(volume, mug.geometry.volume * 1.05);
  // Taken as not closed (a scan with holes), the mug weighs as its parts.
  db::ObjectDatabase open = mug;
  open.geometry.closed = false;
  const MassProperties parts = objectMassProperties(open, 1000.0);
  EXPECT_NEAR(parts.mass, 1000.0 * volume, 1e-9);
  const MassProperties solid = objectMassProperties(mug, 1000.0);
  EXPECT_LT((parts.center_of_mass - solid.center_of_mass).norm(), 0.003);
}

}  // namespace
}  // namespace hfts::physics
