#include "robot/plan_export.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/invalid_argument.h"
#include "robot/kinematics.h"
#include "robot/point_cloud.h"
#include "robot/scene_export.h"

#include "robot_fixture.h"
#include "test_meshes.h"

namespace hfts::robot {
namespace {

PlanAnimation moveA1(const RobotModel& robot) {
  PlanAnimation plan;
  for (int k = 0; k < 5; ++k) {
    const Eigen::VectorXd a1 = Eigen::VectorXd::Unit(robot.numDofs(), 0);
    plan.times.push_back(0.5 * k);
    plan.configurations.push_back(robot.home() + 0.2 * k * a1);
  }
  plan.path = {robot.home(), plan.configurations.back()};
  plan.contacts = Eigen::Matrix3Xd::Zero(3, 2);
  plan.inward_normals = Eigen::Matrix3Xd::Zero(3, 2);
  plan.inward_normals.row(2).setOnes();
  return plan;
}

TEST(PlanExport, EveryLinkWithGeometryIsAnimatedAlongTheGivenTimes) {
  const RobotModel& robot = test::kr5Sdh();
  const PlanAnimation plan = moveA1(robot);
  const std::string glb = planGlb(robot, Scene{}, nullptr, plan);
  ASSERT_GT(glb.size(), 12u);
  EXPECT_EQ(glb.substr(0, 4), "glTF");

  Assimp::Importer importer;
  const aiScene* read = importer.ReadFileFromMemory(glb.data(), glb.size(), 0, "glb");
  ASSERT_NE(read, nullptr) << importer.GetErrorString();
  ASSERT_EQ(read->mNumAnimations, 1u);
  const aiAnimation& a = *read->mAnimations[0];
  std::size_t withGeometry = 0;
  for (const Link& l : robot.links()) withGeometry += l.shapes.empty() ? 0 : 1;
  EXPECT_EQ(a.mNumChannels, withGeometry);
  const aiNodeAnim* palm = nullptr;
  for (unsigned c = 0; c < a.mNumChannels; ++c)
    if (std::strcmp(a.mChannels[c]->mNodeName.C_Str(), "palm") == 0) palm = a.mChannels[c];
  ASSERT_NE(palm, nullptr);
  ASSERT_EQ(palm->mNumPositionKeys, plan.times.size());
  // The last key is the palm's pose at the last configuration.
  const Eigen::Vector3d expected =
      forwardKinematics(robot, plan.configurations.back())[robot.palmLink()].translation();
  const aiVector3D& last = palm->mPositionKeys[plan.times.size() - 1].mValue;
  EXPECT_NEAR(last.x, expected.x(), 1e-5);
  EXPECT_NEAR(last.y, expected.y(), 1e-5);
  EXPECT_NEAR(last.z, expected.z(), 1e-5);
  EXPECT_NE(read->mRootNode->FindNode("path"), nullptr);
  EXPECT_NE(read->mRootNode->FindNode("contacts"), nullptr);
}

/// `plan` with a simulated motion: the arm still, the object (a cube)
/// rising 10 cm in 1 s.
PlanAnimation withSimulatedLift(PlanAnimation plan, const RobotModel& robot) {
  for (int k = 0; k <= 10; ++k) {
    plan.simulated_times.push_back(0.1 * k);
    plan.simulated_configurations.push_back(robot.home());
    plan.simulated_object.push_back(Eigen::Translation3d(0.5, 0.0, 0.01 * k) *
                                    Eigen::Isometry3d::Identity());
  }
  plan.object_pose = Eigen::Translation3d(0.5, 0.0, 0.0) * Eigen::Isometry3d::Identity();
  return plan;
}

const aiNodeAnim* channelOf(const aiAnimation& a, const char* node) {
  for (unsigned c = 0; c < a.mNumChannels; ++c)
    if (std::strcmp(a.mChannels[c]->mNodeName.C_Str(), node) == 0) return a.mChannels[c];
  return nullptr;
}

TEST(PlanExport, ASimulatedMotionIsASecondAnimationThatMovesTheObjectToo) {
  const RobotModel& robot = test::kr5Sdh();
  const db::ObjectGeometry object = test::meshObject(test::cube(0.04));
  Scene scene;
  scene.target_object = "cube";
  const std::string glb = planGlb(robot, scene, &object, withSimulatedLift(moveA1(robot), robot));
  Assimp::Importer importer;
  const aiScene* read = importer.ReadFileFromMemory(glb.data(), glb.size(), 0, "glb");
  ASSERT_NE(read, nullptr) << importer.GetErrorString();
  ASSERT_EQ(read->mNumAnimations, 2u);
  const aiAnimation& plan = *read->mAnimations[0];
  const aiAnimation& simulated = *read->mAnimations[1];
  EXPECT_STREQ(plan.mName.C_Str(), "plan");
  EXPECT_STREQ(simulated.mName.C_Str(), "simulated");
  // Both move the links and the object's node: the plan holds it where
  // its mesh stands, the simulation lifts it 10 cm.
  ASSERT_EQ(plan.mNumChannels, simulated.mNumChannels);
  const aiNodeAnim* still = channelOf(plan, "cube");
  const aiNodeAnim* lifted = channelOf(simulated, "cube");
  ASSERT_NE(still, nullptr);
  ASSERT_NE(lifted, nullptr);
  const aiVector3D& held = still->mPositionKeys[still->mNumPositionKeys - 1].mValue;
  EXPECT_NEAR(held.Length(), 0.0, 1e-6);
  ASSERT_EQ(lifted->mNumPositionKeys, 11u);
  const aiVector3D& top = lifted->mPositionKeys[10].mValue;
  EXPECT_NEAR(top.x, 0.0, 1e-6);
  EXPECT_NEAR(top.y, 0.0, 1e-6);
  EXPECT_NEAR(top.z, 0.1, 1e-6);
  EXPECT_NE(channelOf(simulated, "palm"), nullptr);
}

TEST(PlanExport, AnObjectThePlanCarriesMovesInThePlansAnimation) {
  const RobotModel& robot = test::kr5Sdh();
  const db::ObjectGeometry object = test::meshObject(test::cube(0.04));
  Scene scene;
  scene.target_object = "cube";
  PlanAnimation carried = moveA1(robot);
  carried.object_pose = Eigen::Translation3d(0.5, 0.0, 0.0) * Eigen::Isometry3d::Identity();
  for (std::size_t k = 0; k < carried.times.size(); ++k)
    carried.object_motion.push_back(Eigen::Translation3d(0.5, 0.0, 0.02 * k) *
                                    Eigen::Isometry3d::Identity());
  for (const bool simulated : {false, true}) {
    const PlanAnimation plan = simulated ? withSimulatedLift(carried, robot) : carried;
    const std::string glb = planGlb(robot, scene, &object, plan);
    Assimp::Importer importer;
    const aiScene* read = importer.ReadFileFromMemory(glb.data(), glb.size(), 0, "glb");
    ASSERT_NE(read, nullptr) << importer.GetErrorString();
    ASSERT_EQ(read->mNumAnimations, simulated ? 2u : 1u);
    const aiNodeAnim* cube = channelOf(*read->mAnimations[0], "cube");
    ASSERT_NE(cube, nullptr);
    ASSERT_EQ(cube->mNumPositionKeys, 5u);
    // Moved from where its mesh stands: 8 cm up at the end.
    EXPECT_NEAR(cube->mPositionKeys[4].mValue.z, 0.08, 1e-6);
    EXPECT_NEAR(cube->mPositionKeys[0].mValue.Length(), 0.0, 1e-6);
  }
}

/// The JSON chunk of a binary glTF: the first, after the 12-byte header
/// and its own length and type.
nlohmann::json gltfJson(const std::string& glb) {
  std::uint32_t length = 0;
  std::memcpy(&length, glb.data() + 12, sizeof length);
  EXPECT_EQ(glb.substr(16, 4), "JSON");
  return nlohmann::json::parse(glb.substr(20, length));
}

/// The primitive of the mesh of the node named `name` in `gltf`, or null.
nlohmann::json primitiveOf(const nlohmann::json& gltf, const std::string& name) {
  for (const nlohmann::json& node : gltf.at("nodes"))
    if (node.contains("name") && node.at("name") == name)
      return gltf.at("meshes").at(node.at("mesh").get<std::size_t>()).at("primitives").at(0);
  return nullptr;
}

/// A scene with one obstacle seen as a cloud of three points, 0.5 m ahead.
Scene sensedScene() {
  CloudOptions options;
  options.radius = 0.0;
  Vertices points(3, 3);
  points << 0, 0, 0, 0.1, 0, 0, 0, 0.1, 0.05;
  auto cloud = std::make_shared<VoxelCloud>(voxelize(points, options));
  Obstacle seen;
  seen.name = "seen";
  seen.type = Obstacle::Type::kPoints;
  seen.pose = Eigen::Translation3d(0.5, 0.0, 0.2) * Eigen::Isometry3d::Identity();
  seen.cloud = cloud;
  seen.mesh = cloud->mesh;
  seen.distance_grid = std::shared_ptr<const db::DistanceGrid>(cloud, &cloud->distances);
  Scene scene;
  scene.obstacles.push_back(seen);
  return scene;
}

TEST(PlanExport, ASensedObstacleIsItsVoxelsAndItsPointsInTheWorld) {
  const RobotModel& robot = test::kr5Sdh();
  const Scene scene = sensedScene();
  const std::filesystem::path sceneGlb =
      std::filesystem::temp_directory_path() /
      ("hfts-sensed-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + ".glb");
  exportSceneGlb(robot, scene, nullptr, robot.home(), sceneGlb);
  std::ostringstream sceneBytes;
  sceneBytes << std::ifstream(sceneGlb, std::ios::binary).rdbuf();
  std::filesystem::remove(sceneGlb);
  for (const std::string& glb : {planGlb(robot, scene, nullptr, moveA1(robot)), sceneBytes.str()}) {
    const nlohmann::json gltf = gltfJson(glb);
    const nlohmann::json voxels = primitiveOf(gltf, "seen");
    ASSERT_FALSE(voxels.is_null());
    EXPECT_TRUE(!voxels.contains("mode") || voxels.at("mode") == 4)
        << "the voxels' boxes: triangles";
    const nlohmann::json points = primitiveOf(gltf, "seen.points");
    ASSERT_FALSE(points.is_null());
    EXPECT_EQ(points.at("mode"), 0) << "POINTS";
    EXPECT_FALSE(points.contains("indices")) << "every vertex is a point";
    const nlohmann::json& position =
        gltf.at("accessors").at(points.at("attributes").at("POSITION").get<std::size_t>());
    EXPECT_EQ(position.at("count"), 3);
    // In the world frame (the root node turns it to glTF's y up).
    const std::vector<double> low = position.at("min"), high = position.at("max");
    EXPECT_NEAR(low[0], 0.5, 1e-6);
    EXPECT_NEAR(low[1], 0.0, 1e-6);
    EXPECT_NEAR(low[2], 0.2, 1e-6);
    EXPECT_NEAR(high[0], 0.6, 1e-6);
    EXPECT_NEAR(high[1], 0.1, 1e-6);
    EXPECT_NEAR(high[2], 0.25, 1e-6);
  }
}

TEST(PlanExport, BadAnimationsAreRefusedByField) {
  const RobotModel& robot = test::kr5Sdh();
  const auto field = [&](const PlanAnimation& plan) {
    try {
      planGlb(robot, Scene{}, nullptr, plan);
    } catch (const InvalidArgument& e) {
      return e.field();
    }
    return std::string("(accepted)");
  };
  PlanAnimation p = moveA1(robot);
  EXPECT_EQ(field(p), "(accepted)");
  p.times.pop_back();
  EXPECT_EQ(field(p), "configurations");
  p = moveA1(robot);
  p.times[2] = p.times[1];
  EXPECT_EQ(field(p), "times");
  p = moveA1(robot);
  p.configurations[3] = Eigen::VectorXd::Zero(3);
  EXPECT_EQ(field(p), "configurations[3]");
  p = moveA1(robot);
  p.inward_normals = Eigen::Matrix3Xd::Zero(3, 1);
  EXPECT_EQ(field(p), "inward_normals");
  EXPECT_EQ(field(PlanAnimation{}), "times");
  p = withSimulatedLift(moveA1(robot), robot);
  p.simulated_object.pop_back();
  EXPECT_EQ(field(p), "simulated_object");
  p = moveA1(robot);
  p.object_motion.assign(p.times.size() - 1, Eigen::Isometry3d::Identity());
  EXPECT_EQ(field(p), "object_motion");
  p.object_motion.assign(p.times.size(), Eigen::Isometry3d::Identity());
  p.object_motion[1].translation().x() = std::nan("");
  EXPECT_EQ(field(p), "object_motion");
  p = withSimulatedLift(moveA1(robot), robot);
  p.simulated_times[4] = p.simulated_times[3];
  EXPECT_EQ(field(p), "simulated_times");
  p = withSimulatedLift(moveA1(robot), robot);
  p.simulated_configurations[2] = Eigen::VectorXd::Zero(2);
  EXPECT_EQ(field(p), "simulated_configurations[2]");
  EXPECT_THROW(exportPlanGlb(robot, Scene{}, nullptr, moveA1(robot), "plan.gltf"), InvalidArgument);
}

}  // namespace
}  // namespace hfts::robot
