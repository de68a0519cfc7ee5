#include "robot/scene.h"

#include <gtest/gtest.h>

#include <cmath>

#include "robot_fixture.h"
#include "test_meshes.h"

namespace hfts::robot {
namespace {

const char* kMinimal =
    R"({"name": "s", "robot_base": {"position": [0,0,0], "orientation": [0,0,0,1]},
  "obstacles": [], "target": {"object": "mug", "pose": {"position": [0.5,0,0], "orientation": [0,0,0,1]}}})";

/// The scene's error names the bad field's path and the problem.
void expectSceneError(const std::string& text, const std::string& field,
                      const std::string& problem) {
  try {
    parseScene(text, ".", "scene 'x'");
    ADD_FAILURE() << "accepted; expected " << field << ": " << problem;
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), field);
    EXPECT_EQ(e.problem().substr(0, problem.size()), problem) << e.what();
    const std::string prefix = "scene 'x': " + (field.empty() ? "" : field + ": ");
    EXPECT_EQ(std::string(e.what()).substr(0, prefix.size()), prefix) << e.what();
  }
}

std::string withObstacle(const std::string& obstacle) {
  std::string text = kMinimal;
  text.replace(text.find("\"obstacles\": []"), 15, "\"obstacles\": [" + obstacle + "]");
  return text;
}

TEST(Scene, BundledScenesLoad) {
  for (const char* name : {"table", "shelf", "bin"}) {
    const Scene s = loadScene(test::sourcePath(std::string("objects/scenes/") + name + ".json"));
    EXPECT_EQ(s.name, name);
    EXPECT_GE(s.obstacles.size(), 5u);
    EXPECT_FALSE(s.target_object.empty());
  }
}

TEST(Scene, ParsesPosesInRosQuaternionOrder) {
  const std::string text = withObstacle(
      R"({"name": "b", "type": "box", "size": [1,2,3], "pose": {"position": [1,2,3], "orientation": [0,0,0.7071067811865476,0.7071067811865476]}})");
  const Scene s = parseScene(text, ".", "x");
  ASSERT_EQ(s.obstacles.size(), 1u);
  EXPECT_TRUE(s.obstacles[0].pose.linear().col(0).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  EXPECT_FALSE(s.start.has_value());
}

TEST(Scene, StartsPerRobotOrForAnyRobot) {
  const Scene shelf = loadScene(test::sourcePath("objects/scenes/shelf.json"));
  EXPECT_FALSE(shelf.start.has_value());
  ASSERT_TRUE(shelf.startFor("kr5_sdh").has_value());
  EXPECT_EQ(shelf.startFor("kr5_sdh")->size(), 13);
  EXPECT_EQ((*shelf.startFor("kr5_sdh"))(0), 1.2);  // turned away from the cabinet
  EXPECT_EQ(shelf.startFor("panda_gripper")->size(), 8);
  EXPECT_FALSE(shelf.startFor("another_robot").has_value());  // its home
  std::string text = kMinimal;
  text.insert(text.size() - 1, R"(, "start": [0.1, 0.2])");
  EXPECT_EQ(*parseScene(text, ".", "x").startFor("any"), Eigen::Vector2d(0.1, 0.2));
  text = kMinimal;
  text.insert(text.size() - 1, R"(, "start": {"r": [0.1, "x"]})");
  expectSceneError(text, "start.r", "");
  text = kMinimal;
  text.insert(text.size() - 1, R"(, "start": {"../r": [0.1]})");
  expectSceneError(text, "start.../r", "must be a robot name");
}

TEST(Scene, MeshObstaclesLoadRelativeToTheSceneFile) {
  test::TempDir dir;
  test::writeBinaryStl(dir / "block.stl", test::cube(0.1));
  const std::string text = withObstacle(
      R"({"name": "m", "type": "mesh", "mesh": "block.stl", "scale": 2, "pose": {"position": [0,0,0], "orientation": [0,0,0,1]}})");
  const Scene s = parseScene(text, dir.path(), "x");
  EXPECT_NEAR(s.obstacles[0].mesh.vertices.maxCoeff(), 0.1, 1e-7);
}

TEST(Scene, MeshObstaclesGetTheDistanceGridOfTheirMesh) {
  test::TempDir dir;
  test::writeBinaryStl(dir / "block.stl", test::cube(0.1));
  TriangleMesh openBox = test::cube(0.1);  // without its top (rows 2 and 3): open
  openBox.triangles.middleRows(2, 2) = openBox.triangles.bottomRows(2);
  openBox.triangles.conservativeResize(10, 3);
  test::writeBinaryStl(dir / "open.stl", openBox);
  const std::string text = withObstacle(
      R"({"name": "m", "type": "mesh", "mesh": "block.stl", "scale": 2, "pose": {"position": [1,0,0], "orientation": [0,0,0,1]}},
         {"name": "s", "type": "mesh", "mesh": "open.stl", "pose": {"position": [0,0,0], "orientation": [0,0,0,1]}},
         {"name": "b", "type": "box", "size": [1,1,1], "pose": {"position": [0,0,2], "orientation": [0,0,0,1]}})");
  const Scene s = parseScene(text, dir.path(), "x");
  ASSERT_EQ(s.obstacles.size(), 3u);
  // The closed block (scaled to 20 cm) gets a signed grid in its mesh frame.
  ASSERT_NE(s.obstacles[0].distance_grid, nullptr);
  const db::DistanceGrid& block = *s.obstacles[0].distance_grid;
  EXPECT_TRUE(block.is_signed);
  EXPECT_TRUE((block.origin.array() <= -0.13).all());  // 10 cm + the 3 cm margin
  EXPECT_NEAR(block.lowerBound(Eigen::Vector3d(0.15, 0, 0)), 0.05, std::sqrt(3.0) * block.spacing);
  EXPECT_LT(block.lowerBound(Eigen::Vector3d::Zero()), -0.05);
  // The open box gets an unsigned one; primitives get none.
  ASSERT_NE(s.obstacles[1].distance_grid, nullptr);
  EXPECT_FALSE(s.obstacles[1].distance_grid->is_signed);
  EXPECT_EQ(s.obstacles[2].distance_grid, nullptr);
  // Copies of the scene share the grid.
  const Scene copy = s;
  EXPECT_EQ(copy.obstacles[0].distance_grid, s.obstacles[0].distance_grid);
}

TEST(Scene, MalformedScenesGiveClearErrors) {
  expectSceneError("{", "", "not valid JSON");
  expectSceneError("[]", "", "must be a JSON object");
  std::string text = kMinimal;
  expectSceneError(text.substr(0, text.find("\"target\"") - 2) + "}", "target", "is required");
  expectSceneError(
      withObstacle(
          R"({"name": "b", "type": "cone", "pose": {"position": [0,0,0], "orientation": [0,0,0,1]}})"),
      "obstacles[0].type",
      "must be box, cylinder, sphere, mesh, points or depth_image, got 'cone'");
  expectSceneError(
      withObstacle(
          R"({"name": "b", "type": "box", "size": [1,-2,3], "pose": {"position": [0,0,0], "orientation": [0,0,0,1]}})"),
      "obstacles[0].size", "must be positive");
  expectSceneError(
      withObstacle(
          R"({"name": "b", "type": "sphere", "radius": 0.1, "pose": {"position": [0,0,0], "orientation": [0,0,0,0]}})"),
      "obstacles[0].pose.orientation", "is a quaternion of zero norm");
  expectSceneError(
      withObstacle(
          R"({"name": "b", "type": "sphere", "radius": 0.1, "pose": {"position": [0,0], "orientation": [0,0,0,1]}})"),
      "obstacles[0].pose.position", "must be an array of 3 numbers");
  expectSceneError(
      withObstacle(
          R"({"name": "b", "type": "mesh", "mesh": "missing.stl", "pose": {"position": [0,0,0], "orientation": [0,0,0,1]}})"),
      "obstacles[0].mesh", "");
  test::expectErrorMentioning<SceneError>(
      [] {
        parseScene(
            withObstacle(
                R"({"name": "b", "type": "mesh", "mesh": "missing.stl", "pose": {"position": [0,0,0], "orientation": [0,0,0,1]}})"),
            ".", "x");
      },
      {"obstacles[0].mesh: ", "missing.stl"});
  text = kMinimal;
  text.replace(text.find("\"mug\""), 5, "\"../etc/passwd\"");
  expectSceneError(text, "target.object", "must be a database name without path characters");
  test::expectErrorMentioning<SceneError>([] { loadScene("/nonexistent/scene.json"); },
                                          {"/nonexistent/scene.json", "cannot read"});
}

// Found by fuzzing (scene_fuzzer): a bad cylinder or sphere field threw out
// of an unfinished Eigen comma initialiser, whose destructor asserts.
TEST(Scene, BadCylinderAndSphereFieldsGiveClearErrors) {
  const std::string pose = R"("pose": {"position": [0,0,0], "orientation": [0,0,0,1]})";
  expectSceneError(
      withObstacle(R"({"name": "c", "type": "cylinder", "radius": 0.1, )" + pose + "}"),
      "obstacles[0].length", "is required");
  expectSceneError(
      withObstacle(R"({"name": "c", "type": "cylinder", "radius": -1, "length": 1, )" + pose + "}"),
      "obstacles[0].radius", "must be");
  expectSceneError(withObstacle(R"({"name": "s", "type": "sphere", "radius": "r", )" + pose + "}"),
                   "obstacles[0].radius", "must be");
}

TEST(Scene, SafeNamesHaveNoPathCharacters) {
  EXPECT_TRUE(isSafeName("mug"));
  EXPECT_TRUE(isSafeName("l_bracket-2.v1"));
  EXPECT_FALSE(isSafeName(""));
  EXPECT_FALSE(isSafeName("../mug"));
  EXPECT_FALSE(isSafeName("a/b"));
  EXPECT_FALSE(isSafeName(".hidden"));
  EXPECT_FALSE(isSafeName(std::string(200, 'a')));
}

}  // namespace
}  // namespace hfts::robot

namespace hfts::robot {
namespace {

const char* kShelfWithPlacements = R"({
  "name": "s", "robot_base": {"position": [0,0,0], "orientation": [0,0,0,1]},
  "obstacles": [
    {"name": "board", "type": "box", "size": [0.4, 0.6, 0.02],
     "pose": {"position": [0.6, 0, 0.29], "orientation": [0,0,0,1]}},
    {"name": "floor", "type": "box", "size": [2, 2, 0.1],
     "pose": {"position": [0, 0, -0.05], "orientation": [0,0,0,1]}}],
  "target": {"object": "mug", "rest_on": "board",
             "pose": {"position": [0.6, 0, 0.9], "orientation": [0,0,0,1]}},
  "placements": [
    {"name": "lying", "rest_on": "floor",
     "pose": {"position": [0.5, 0.1, 0], "orientation": [0.7071067811865476, 0, 0, 0.7071067811865476]}},
    {"name": "floating", "pose": {"position": [0.4, 0, 0.5], "orientation": [0,0,0,1]}}]})";

/// A 10 cm cube centred on its frame's origin.
Vertices cubeCorners() {
  Vertices v(8, 3);
  for (int i = 0; i < 8; ++i)
    v.row(i) << (i & 1 ? 0.05 : -0.05), (i & 2 ? 0.05 : -0.05), (i & 4 ? 0.05 : -0.05);
  return v;
}

TEST(Scene, PlacementsAndRestOnAreRead) {
  const Scene s = parseScene(kShelfWithPlacements, ".", "x");
  EXPECT_EQ(s.target_rest_on, "board");
  ASSERT_EQ(s.placements.size(), 2u);
  EXPECT_EQ(s.placements[0].name, "lying");
  EXPECT_EQ(s.placements[0].rest_on, "floor");
  EXPECT_EQ(s.placements[1].rest_on, "");
  const Scene lying = s.withPlacement("lying");
  EXPECT_EQ(lying.target_rest_on, "floor");
  EXPECT_TRUE(lying.target_pose.isApprox(s.placements[0].pose));
  EXPECT_TRUE(s.withPlacement("target").target_pose.isApprox(s.target_pose));
  try {
    s.withPlacement("upside_down");
    ADD_FAILURE() << "an unknown placement was accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), "placements");
    EXPECT_NE(e.problem().find("known: target, lying, floating"), std::string::npos) << e.what();
  }
}

TEST(Scene, RestOnMustNameAnObstacle) {
  std::string text = kShelfWithPlacements;
  text.replace(text.find("\"rest_on\": \"board\""), 18, "\"rest_on\": \"shelf\"");
  expectSceneError(text, "target.rest_on", "names no obstacle of the scene: 'shelf'");
  text = kShelfWithPlacements;
  text.replace(text.find("\"rest_on\": \"floor\""), 18, "\"rest_on\": 5");
  expectSceneError(text, "placements[0].rest_on", "must be a string");
  text = kShelfWithPlacements;
  text.replace(text.find("\"floating\""), 10, "\"lying\"");
  expectSceneError(text, "placements[1].name", "'lying' is used twice");
}

TEST(Scene, TopOfAnObstacleIsItsHighestPoint) {
  Obstacle box;
  box.size << 1.0, 1.4, 0.04;
  box.pose.translation() << 0.5, 0, -0.02;
  EXPECT_NEAR(topOf(box), 0.0, 1e-12);
  box.pose.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_NEAR(topOf(box), -0.02 + 0.7, 1e-12);  // stood on its long edge
  Obstacle can;
  can.type = Obstacle::Type::kCylinder;
  can.size << 0.03, 0.2, 0;
  can.pose.translation() << 0, 0, 0.1;
  EXPECT_NEAR(topOf(can), 0.2, 1e-12);
  can.pose.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  EXPECT_NEAR(topOf(can), 0.13, 1e-12);  // lying: its radius above the axis
  Obstacle ball;
  ball.type = Obstacle::Type::kSphere;
  ball.size << 0.04, 0, 0;
  ball.pose.translation() << 0, 0, 0.5;
  EXPECT_NEAR(topOf(ball), 0.54, 1e-12);
}

TEST(Scene, RestingPosePutsTheLowestPointOnTheSupport) {
  const Scene s = parseScene(kShelfWithPlacements, ".", "x");
  const Vertices cube = cubeCorners();
  // The board's top is at 0.30: the cube's centre goes to 0.35 (and the
  // clearance), x and y stay.
  const double gap = kRestingClearance;
  const Eigen::Isometry3d onBoard = targetPose(s, cube);
  EXPECT_NEAR(onBoard.translation().z(), 0.35 + gap, 1e-12);
  EXPECT_NEAR(onBoard.translation().x(), 0.6, 1e-12);
  // Turned 45 degrees about x, its lowest edge is 0.05 sqrt(2) below the centre.
  Scene turned = s;
  turned.target_pose.linear() =
      Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_NEAR(targetPose(turned, cube).translation().z(), 0.30 + gap + 0.05 * std::sqrt(2.0),
              1e-12);
  // Without rest_on the pose is kept as it is.
  EXPECT_TRUE(targetPose(s.withPlacement("floating"), cube).isApprox(s.placements[1].pose));
  EXPECT_NEAR(targetPose(s.withPlacement("lying"), cube).translation().z(), 0.05 + gap, 1e-12);
}

}  // namespace
}  // namespace hfts::robot
