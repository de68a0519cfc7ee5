#include "mujoco_world.h"

#include <gtest/gtest.h>

#include <thread>

#include "panda_cube.h"
#include "physics/mjcf_scene.h"
#include "test_meshes.h"

namespace hfts::physics {
namespace {

std::string pandaCubeXml(const test::PandaCube& world) {
  const ObjectBody body{collisionPieces(test::smallCube()),
                        objectMassProperties(test::smallCube(), 1000.0), world.scene.target_pose};
  return mjcfScene(test::panda(), world.scene, body);
}

TEST(MujocoWorld, ABrokenModelIsRefusedWithMujocosMessage) {
  test::expectErrorMentioning<std::runtime_error>(
      [] { compileMjcf("<mujoco><worldbody><geom type='box'/></worldbody></mujoco>"); },
      {"MuJoCo rejected the generated model", "size"});
}

TEST(MujocoWorld, TheRobotIsPlacedWithItsMimicJointFollowing) {
  const test::PandaCube world;
  const ModelPtr model = compileMjcf(pandaCubeXml(world));
  const WorldIndex index = indexWorld(*model, test::panda());
  ASSERT_EQ(index.mimics.size(), 1u);
  const DataPtr data = makeData(*model);
  setRobotConfiguration(*data, index, world.pregrasp);
  mj_forward(model.get(), data.get());
  EXPECT_EQ(data->qpos[index.mimics[0].qpos], world.pregrasp(7));
  EXPECT_TRUE(robotConfiguration(*data, index).isApprox(world.pregrasp, 0.0));
  // The palm where the robot's own kinematics puts it: above the cube.
  const Eigen::Isometry3d palm = bodyPose(*data, index.palm_body);
  EXPECT_TRUE(palm.translation().isApprox(
      world.center() + Eigen::Vector3d(0, 0, test::kPandaPadDepth), 1e-6));
  EXPECT_LT(palm.linear().col(2).dot(Eigen::Vector3d::UnitZ()), -0.999999);
  ASSERT_EQ(index.fingertip_bodies.size(), 2u);
}

TEST(MujocoWorld, TheObjectIsWhereItIsPut) {
  const test::PandaCube world;
  const ModelPtr model = compileMjcf(pandaCubeXml(world));
  const WorldIndex index = indexWorld(*model, test::panda());
  const DataPtr data = makeData(*model);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d(0, 1, 1).normalized()).matrix();
  pose.translation() = Eigen::Vector3d(0.1, 0.2, 0.3);
  setObjectPose(*data, index, pose);
  mj_forward(model.get(), data.get());
  EXPECT_TRUE(bodyPose(*data, index.object_body).isApprox(pose, 1e-12));
}

TEST(MujocoWorld, ModelsCompileOnSeveralThreadsAtOnce) {
  const test::PandaCube world;
  const std::string xml = pandaCubeXml(world);
  std::vector<int> bodies(4, 0);
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < bodies.size(); ++t)
    threads.emplace_back([&, t] { bodies[t] = compileMjcf(xml)->nbody; });
  for (std::thread& t : threads) t.join();
  for (const int n : bodies) EXPECT_EQ(n, 14);  // the world, 12 links, the object
}

}  // namespace
}  // namespace hfts::physics
