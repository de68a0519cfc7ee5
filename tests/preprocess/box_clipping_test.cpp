#include "box_clipping.h"

#include <gtest/gtest.h>

#include <numeric>

#include "test_meshes.h"

namespace hfts::preprocess {
namespace {

std::vector<std::uint32_t> all(const TriangleMesh& mesh) {
  std::vector<std::uint32_t> out(static_cast<std::size_t>(mesh.triangles.rows()));
  std::iota(out.begin(), out.end(), 0u);
  return out;
}

/// The points as rows.
Vertices rows(const std::vector<double>& xyz) {
  Vertices v(static_cast<Eigen::Index>(xyz.size() / 3), 3);
  std::copy(xyz.begin(), xyz.end(), v.data());
  return v;
}

TEST(BoxClipping, TrianglesMeetingTheBoxIncludeThoseThatTouchIt) {
  const TriangleMesh cube = test::cube(0.1);  // faces at +-0.05
  EXPECT_EQ(trianglesMeeting(cube, all(cube), {{-1, -1, -1}, {1, 1, 1}}).size(), 12u);
  // A box beyond x = 0.05 that touches the x+ face: that face's two
  // triangles and the eight of the faces that reach it.
  EXPECT_EQ(trianglesMeeting(cube, all(cube), {{0.05, -1, -1}, {1, 1, 1}}).size(), 10u);
  EXPECT_TRUE(trianglesMeeting(cube, all(cube), {{0.06, -1, -1}, {1, 1, 1}}).empty());
}

TEST(BoxClipping, ClippingCutsTrianglesOnThePlanesExactly) {
  // The cube's top and bottom cut at x = 0.01: every new corner has x = 0.01.
  const TriangleMesh cube = test::cube(0.1);
  const Box3 box{{-1, -1, -1}, {0.01, 1, 1}};
  std::vector<double> xyz;
  appendClippedCorners(cube, all(cube), box, xyz);
  const Vertices p = rows(xyz);
  int onCut = 0;
  for (Eigen::Index i = 0; i < p.rows(); ++i) {
    EXPECT_LE(p(i, 0), 0.01);
    onCut += p(i, 0) == 0.01 ? 1 : 0;
  }
  EXPECT_GE(onCut, 4);                                         // the section's corners
  EXPECT_GE((p.array() == -0.05).rowwise().all().count(), 1);  // the corner (-,-,-)
}

TEST(BoxClipping, WhatLiesInTheBoxsBoundaryIsLeftOut) {
  // The box above the cube's top face: the side faces touch it along their
  // top edges (no area in it) and the top face lies in its bottom face.
  const TriangleMesh cube = test::cube(0.1);
  std::vector<double> xyz;
  appendClippedCorners(cube, all(cube), {{-1, -1, 0.05}, {1, 1, 1}}, xyz);
  EXPECT_TRUE(xyz.empty());
  // An L of two blocks cut along the arm's inner face (x = 2 cm): the base
  // beside it gets none of that face, which reaches up to 6 cm.
  const TriangleMesh l = test::merged(test::block({0, 0, 0}, {0.1, 0.04, 0.02}),
                                      test::block({0, 0, 0}, {0.02, 0.04, 0.06}));
  appendClippedCorners(l, all(l), {{0.02, 0, 0}, {0.1, 0.04, 0.06}}, xyz);
  ASSERT_FALSE(xyz.empty());
  for (std::size_t i = 2; i < xyz.size(); i += 3) EXPECT_LE(xyz[i], 0.02);
}

TEST(BoxClipping, JustInsideMovesAPointOffTheFacesItLiesOn) {
  const Box3 box{{0, 0, 0}, {1, 2, 3}};
  const Eigen::Vector3d q = justInside(box, {0, 2, 1.5});
  EXPECT_GT(q.x(), 0.0);
  EXPECT_LT(q.x(), 1e-5);
  EXPECT_LT(q.y(), 2.0);
  EXPECT_EQ(q.z(), 1.5);
}

}  // namespace
}  // namespace hfts::preprocess
