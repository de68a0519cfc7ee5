#include "robot/scene.h"

#include <gtest/gtest.h>

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

TEST(Scene, MeshObstaclesLoadRelativeToTheSceneFile) {
  test::TempDir dir;
  test::writeBinaryStl(dir / "block.stl", test::cube(0.1));
  const std::string text = withObstacle(
      R"({"name": "m", "type": "mesh", "mesh": "block.stl", "scale": 2, "pose": {"position": [0,0,0], "orientation": [0,0,0,1]}})");
  const Scene s = parseScene(text, dir.path(), "x");
  EXPECT_NEAR(s.obstacles[0].mesh.vertices.maxCoeff(), 0.1, 1e-7);
}

TEST(Scene, MalformedScenesGiveClearErrors) {
  expectSceneError("{", "", "not valid JSON");
  expectSceneError("[]", "", "must be a JSON object");
  std::string text = kMinimal;
  expectSceneError(text.substr(0, text.find("\"target\"") - 2) + "}", "target", "is required");
  expectSceneError(
      withObstacle(
          R"({"name": "b", "type": "cone", "pose": {"position": [0,0,0], "orientation": [0,0,0,1]}})"),
      "obstacles[0].type", "must be box, cylinder, sphere or mesh, got 'cone'");
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
