// Place goals (planner/place_goal.h): the region on a support's top, the
// ways of resting a goal allows and that fit there (or why none), whether
// a placement stands on the region, and random placements on it.
#include "planner/place_goal.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/invalid_argument.h"
#include "test_meshes.h"

namespace hfts::planner {
namespace {

/// A table whose top (1.0 x 0.6 m) is at z = 0.75, turned 30 degrees
/// about z; a cylinder; a tilted board; a small stool (5 x 5 cm top).
robot::Scene scene() {
  robot::Scene s;
  s.name = "places";
  const auto box = [&](const std::string& name, const Eigen::Vector3d& size,
                       const Eigen::Isometry3d& pose) {
    robot::Obstacle o;
    o.name = name;
    o.type = robot::Obstacle::Type::kBox;
    o.size = size;
    o.pose = pose;
    s.obstacles.push_back(o);
  };
  Eigen::Isometry3d table = Eigen::Isometry3d::Identity();
  table.linear() = Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  table.translation() = Eigen::Vector3d(0.6, 0.1, 0.725);
  box("table", Eigen::Vector3d(1.0, 0.6, 0.05), table);
  Eigen::Isometry3d board = Eigen::Isometry3d::Identity();
  board.linear() = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()).toRotationMatrix();
  box("tilted", Eigen::Vector3d(0.3, 0.3, 0.02), board);
  box("stool", Eigen::Vector3d(0.05, 0.05, 0.4),
      Eigen::Isometry3d(Eigen::Translation3d(2, 0, 0.2)));
  robot::Obstacle post;
  post.name = "post";
  post.type = robot::Obstacle::Type::kCylinder;
  post.size = Eigen::Vector3d(0.05, 0.5, 0);
  s.obstacles.push_back(post);
  return s;
}

/// A 10 x 6 x 20 cm box object (its hull the box), centre of mass in the
/// middle; `turned` rotates its vertices 45 degrees about x, so that no
/// face points down its own -z.
db::ObjectDatabase boxObject(bool turned = false) {
  TriangleMesh mesh =
      test::block(Eigen::Vector3d(-0.05, -0.03, -0.1), Eigen::Vector3d(0.05, 0.03, 0.1));
  if (turned)
    mesh.vertices =
        (mesh.vertices * Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitX()).toRotationMatrix())
            .eval();
  db::ObjectDatabase object;
  object.name = turned ? "turned_box" : "box";
  object.geometry = test::meshObject(mesh);
  object.geometry.hull_vertices = mesh.vertices;
  object.geometry.hull_faces = mesh.triangles;
  object.geometry.center_of_mass = Eigen::Vector3d::Zero();
  return object;
}

TEST(PlaceGoal, TheRegionIsTheTopOfALevelBox) {
  const PlaceRegion region = placeRegion(scene(), {"table", std::nullopt, false});
  EXPECT_EQ(region.support, "table");
  EXPECT_NEAR(region.frame.translation().z(), 0.75, 1e-12);
  EXPECT_TRUE(region.half_extents.isApprox(Eigen::Vector2d(0.5, 0.3)));
  EXPECT_NEAR(region.frame.linear().col(2).z(), 1.0, 1e-12);
}

TEST(PlaceGoal, BadRegionsAreRefusedByName) {
  const robot::Scene s = scene();
  test::expectErrorMentioning<InvalidArgument>(
      [&] {
        placeRegion(s, {"shelf", std::nullopt, false});
      },
      {"place.on", "no obstacle 'shelf'", "table, tilted, stool, post"});
  test::expectErrorMentioning<InvalidArgument>(
      [&] {
        placeRegion(s, {"post", std::nullopt, false});
      },
      {"place.on", "not a box"});
  test::expectErrorMentioning<InvalidArgument>(
      [&] {
        placeRegion(s, {"tilted", std::nullopt, false});
      },
      {"place.on", "not level", "5.73 degrees"});
  test::expectErrorMentioning<InvalidArgument>(
      [&] {
        placeRegion(
            s, {"table", Eigen::AlignedBox2d(Eigen::Vector2d(0, 0), Eigen::Vector2d(0, 1)), false});
      },
      {"place.area", "min < max"});
  test::expectErrorMentioning<InvalidArgument>(
      [&] {
        placeRegion(
            s, {"table", Eigen::AlignedBox2d(Eigen::Vector2d(5, 5), Eigen::Vector2d(6, 6)), false});
      },
      {"place.area", "off the top of 'table'"});
}

TEST(PlaceGoal, TheFacesAGoalAllowsOrWhyNone) {
  const robot::Scene s = scene();
  const PlaceRegion table = placeRegion(s, {"table", std::nullopt, false});
  EXPECT_EQ(placeFaces(boxObject(), table, {"table", std::nullopt, false}).size(), 6u);
  const std::vector<grasp::RestingFace> upright =
      placeFaces(boxObject(), table, {"table", std::nullopt, true});
  ASSERT_EQ(upright.size(), 1u);
  EXPECT_NEAR(upright.front().normal.z(), -1.0, 1e-12);
  std::string why;
  EXPECT_TRUE(placeFaces(boxObject(true), table, {"table", std::nullopt, true}, &why).empty());
  EXPECT_EQ(why, "'turned_box' stands upright on none of its 6 stable faces");
  // On a 5 x 5 cm stool the box stands on its 10 x 6 end at no yaw, nor
  // on any other face.
  const PlaceRegion stool = placeRegion(s, {"stool", std::nullopt, false});
  EXPECT_TRUE(placeFaces(boxObject(), stool, {"stool", std::nullopt, false}, &why).empty());
  EXPECT_EQ(why, "none of the 6 ways 'box' rests fits on 'stool' (top 0.05 x 0.05 m)");
  // A ball (a 32 x 16 facet sphere of 4 cm) rests on no face.
  std::vector<Eigen::Vector2d> profile;
  for (int k = 0; k <= 16; ++k)
    profile.emplace_back(0.04 * std::sin(M_PI * k / 16), -0.04 * std::cos(M_PI * k / 16));
  const TriangleMesh sphere = test::revolved(profile, 32);
  db::ObjectDatabase ball;
  ball.name = "ball";
  ball.geometry = test::meshObject(sphere);
  ball.geometry.hull_vertices = sphere.vertices;
  ball.geometry.hull_faces = sphere.triangles;
  EXPECT_TRUE(placeFaces(ball, table, {"table", std::nullopt, false}, &why).empty());
  EXPECT_EQ(why, "'ball' rests stably on no face (it rolls or tips over)");
}

TEST(PlaceGoal, RandomPlacementsStandOnTheRegionWithinTheArea) {
  const robot::Scene s = scene();
  const db::ObjectDatabase box = boxObject();
  const Eigen::AlignedBox2d area(Eigen::Vector2d(0.5, 0.0), Eigen::Vector2d(0.7, 0.2));
  for (const std::optional<Eigen::AlignedBox2d>& within :
       {std::optional<Eigen::AlignedBox2d>{}, std::optional(area)}) {
    const PlaceGoal goal{"table", within, false};
    const PlaceRegion region = placeRegion(s, goal);
    const std::vector<grasp::RestingFace> faces = placeFaces(box, region, goal);
    std::mt19937_64 rng(4);
    for (int i = 0; i < 200; ++i) {
      const std::optional<Eigen::Isometry3d> pose =
          samplePlacement(region, faces, box.geometry.center_of_mass, rng);
      ASSERT_TRUE(pose.has_value());
      // Its lowest point 1 mm above the top, every hull vertex over it.
      double lowest = 1e9;
      for (Eigen::Index v = 0; v < box.geometry.hull_vertices.rows(); ++v) {
        const Eigen::Vector3d p = *pose * box.geometry.hull_vertices.row(v).transpose();
        lowest = std::min(lowest, p.z());
      }
      EXPECT_NEAR(lowest, 0.75 + robot::kRestingClearance, 1e-9);
      if (within) {
        EXPECT_TRUE(area.contains((*pose * box.geometry.center_of_mass).head<2>()));
      }
    }
  }
  // A pose over the table's edge is not supported.
  const PlaceRegion region = placeRegion(s, {"table", std::nullopt, false});
  const grasp::RestingFace flat = placeFaces(box, region, {"table", std::nullopt, false})[0];
  const Eigen::Vector3d edge = region.frame * Eigen::Vector3d(0.5, 0.0, 0.0);
  EXPECT_FALSE(
      supported(region, flat, Eigen::Vector3d::Zero(),
                grasp::restingPose(flat, Eigen::Vector3d::Zero(), edge.head<2>(), 0.0, 0.751)));
  const Eigen::Vector3d middle = region.frame * Eigen::Vector3d(0.1, 0.05, 0.0);
  EXPECT_TRUE(
      supported(region, flat, Eigen::Vector3d::Zero(),
                grasp::restingPose(flat, Eigen::Vector3d::Zero(), middle.head<2>(), 1.0, 0.751)));
  // Nothing to draw from: none.
  std::mt19937_64 rng(1);
  EXPECT_FALSE(samplePlacement(region, {}, Eigen::Vector3d::Zero(), rng).has_value());
}

}  // namespace
}  // namespace hfts::planner
