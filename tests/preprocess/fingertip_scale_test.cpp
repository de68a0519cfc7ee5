#include <gtest/gtest.h>

#include <cmath>

#include "preprocess/fingertip_scale.h"
#include "test_meshes.h"

namespace hfts::preprocess {
namespace {

TEST(FingertipScale, TheScalesLeftZeroFollowThePad) {
  db::BuildParameters params;
  params.pad_radius = 0.014;  // the SDH's
  const db::BuildParameters r = resolveFilterScales(params, 200000.0);
  EXPECT_DOUBLE_EQ(r.patch_radius, 0.007);
  EXPECT_EQ(r.max_hull_distance, params.max_hull_distance);  // the finger's reach, not the pad's
  // A third of the 30.8 samples a 7 mm disc holds at 200 000 per m^2.
  EXPECT_EQ(r.min_neighbours, 10u);
  EXPECT_EQ(r.max_curvature, params.max_curvature);  // scale-free
}

TEST(FingertipScale, TheDefaultsSuitTheSmallestBundledPad) {
  const db::BuildParameters r = resolveFilterScales({}, 200000.0);
  EXPECT_DOUBLE_EQ(r.pad_radius, 0.008);  // the Panda gripper's finger pads
  EXPECT_DOUBLE_EQ(r.patch_radius, 0.004);
  EXPECT_EQ(r.min_neighbours, 3u);
}

TEST(FingertipScale, ScalesGivenAreKept) {
  db::BuildParameters params;
  params.patch_radius = 0.01;
  params.min_neighbours = 7;
  const db::BuildParameters r = resolveFilterScales(params, 200000.0);
  EXPECT_EQ(r.patch_radius, 0.01);
  EXPECT_EQ(r.min_neighbours, 7u);
}

TEST(FingertipScale, SparseSamplesStillNeedOneNeighbour) {
  EXPECT_EQ(resolveFilterScales({}, 100.0).min_neighbours, 1u);
}

TEST(FingertipScale, BadPadsAndDensitiesAreRejectedByName) {
  db::BuildParameters params;
  params.pad_radius = -0.01;
  test::expectErrorMentioning<std::invalid_argument>([&] { resolveFilterScales(params, 200000.0); },
                                                     {"pad_radius", "-0.01"});
  test::expectErrorMentioning<std::invalid_argument>([&] { resolveFilterScales({}, std::nan("")); },
                                                     {"samplesPerSquareMetre"});
}

}  // namespace
}  // namespace hfts::preprocess
