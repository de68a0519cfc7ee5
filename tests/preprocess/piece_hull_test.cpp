#include "piece_hull.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <random>

#include "test_meshes.h"

namespace hfts::preprocess {
namespace {

std::vector<double> flat(const Vertices& v) {
  std::vector<double> xyz;
  for (Eigen::Index i = 0; i < v.rows(); ++i) xyz.insert(xyz.end(), {v(i, 0), v(i, 1), v(i, 2)});
  return xyz;
}

/// A cube's corners, points on its faces and inside, and duplicates.
Vertices cloud(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  Vertices v(8 + 60, 3);
  v.topRows(8) = test::cube(0.1).vertices;
  for (Eigen::Index i = 8; i < v.rows(); ++i) {
    v.row(i) << u(rng), u(rng), u(rng);
    if (i % 3 == 0) v(i, i % 2) = 0.05;       // on a face
    if (i % 7 == 0) v.row(i) = v.row(i % 8);  // a corner again
  }
  return v;
}

TEST(PieceHull, OfACubeCloudIsTheCubeInCanonicalOrder) {
  const db::ConvexPiece piece = pieceHull(flat(cloud(1)));
  ASSERT_EQ(piece.vertices.rows(), 8);
  EXPECT_EQ(piece.faces.rows(), 12);  // each square a fan of two
  for (Eigen::Index i = 1; i < piece.vertices.rows(); ++i) {
    const auto a = piece.vertices.row(i - 1), b = piece.vertices.row(i);
    EXPECT_TRUE(std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3));
  }
  for (Eigen::Index f = 0; f < piece.faces.rows(); ++f) {
    EXPECT_LT(piece.faces(f, 0), piece.faces(f, 1));  // starts at its smallest vertex
    EXPECT_LT(piece.faces(f, 0), piece.faces(f, 2));
  }
  const TriangleMesh mesh{piece.vertices, piece.faces};
  EXPECT_TRUE(analyzeTopology(mesh).closed());
  EXPECT_NEAR(solidProperties(mesh).volume, 0.001, 1e-15);
  // Counter-clockwise from outside: a positive signed volume.
  double six = 0.0;
  for (Eigen::Index f = 0; f < piece.faces.rows(); ++f)
    six +=
        mesh.vertices.row(piece.faces(f, 0))
            .dot(mesh.vertices.row(piece.faces(f, 1)).cross(mesh.vertices.row(piece.faces(f, 2))));
  EXPECT_GT(six, 0.0);
}

TEST(PieceHull, ACubeIsTheSameWhateverTheOrderOfItsPoints) {
  const db::ConvexPiece first = pieceHull(flat(cloud(1)));
  Vertices shuffled = cloud(1);
  std::mt19937 rng(3);
  for (Eigen::Index i = shuffled.rows() - 1; i > 0; --i)
    shuffled.row(i).swap(shuffled.row(std::uniform_int_distribution<Eigen::Index>(0, i)(rng)));
  const db::ConvexPiece again = pieceHull(flat(shuffled));
  EXPECT_EQ(again.vertices, first.vertices);
  EXPECT_EQ(again.faces, first.faces);
}

TEST(PieceHull, PointsWithoutVolumeGiveNoPiece) {
  EXPECT_EQ(pieceHull({}).vertices.rows(), 0);
  EXPECT_EQ(pieceHull({0, 0, 0, 1, 0, 0, 0, 1, 0}).vertices.rows(), 0);
  EXPECT_EQ(pieceHull(flat(test::square(0.1, 0.02).vertices)).vertices.rows(), 0);
}

}  // namespace
}  // namespace hfts::preprocess
