#pragma once
// The planning tests' world and requests, and what every returned plan
// promises, checked independently of the planner that made it.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>

#include "bundled_objects.h"
#include "grasp/grasp_quality.h"
#include "hfts_db/triangle_bvh.h"
#include "planner/grasp_motion_planner.h"
#include "robot/collision_checker.h"
#include "robot/kinematics.h"
#include "robot_fixture.h"

namespace hfts::test {

/// The planner's final_resolution default: the resolution plans promise.
constexpr double kFinalResolution = 0.0025;

/// The KR5 + SDH with a freshly built hand map and every bundled object,
/// built once per test program.
inline const planner::PlanningWorld& bundledWorld() {
  static const planner::PlanningWorld w(kr5Sdh(), grasp::buildHandMap(kr5Sdh()), bundledObjects());
  return w;
}

/// How much slower the code runs under the sanitizer scripts/sanitize.sh
/// names in HFTS_SANITIZER (1 without one). Plan time limits that a test
/// expects to be met are multiplied by it.
inline double sanitizerSlowdown() {
  const char* sanitizer = std::getenv("HFTS_SANITIZER");
  if (sanitizer == nullptr) return 1.0;
  const std::string name = sanitizer;
  if (name == "address") return 4.0;
  if (name == "thread") return 10.0;
  return name == "undefined" ? 2.0 : 1.0;
}

/// A request in a bundled scene (objects/scenes/<scene>.json), 30 s limit
/// (times sanitizerSlowdown()).
inline planner::PlanRequest bundledSceneRequest(const std::string& scene, const std::string& object,
                                                std::uint64_t seed,
                                                planner::PlanAlgorithm algorithm) {
  planner::PlanRequest r;
  r.scene = robot::loadScene(sourcePath("objects/scenes/" + scene + ".json"));
  r.object = object;
  r.seed = seed;
  r.algorithm = algorithm;
  r.time_limit = 30.0 * sanitizerSlowdown();
  return r;
}

/// The table scene without obstacles and the mug 3 m away, out of the
/// arm's reach: no grasp has an IK solution (1 s limit).
inline planner::PlanRequest outOfReachRequest(planner::PlanAlgorithm algorithm) {
  planner::PlanRequest r = bundledSceneRequest("table", "mug", 1, algorithm);
  r.scene.obstacles.clear();
  r.object_pose = Eigen::Isometry3d(Eigen::Translation3d(3.0, 0.0, 0.0));
  r.time_limit = 1.0;
  return r;
}

/// A scene and an object for parameterised tests, named "scene_object".
struct SceneObject {
  const char* scene;
  const char* object;
};
inline std::string sceneObjectName(const ::testing::TestParamInfo<SceneObject>& param) {
  return std::string(param.param.scene) + "_" + param.param.object;
}

/// The scene a plan was made in: the request's, with the object planned
/// for where it was (the request's pose, else the scene's target pose, put
/// on its support when it rests on one).
inline robot::Scene plannedScene(const planner::PlanningWorld& world,
                                 const planner::PlanRequest& request) {
  const std::string name = request.object.empty() ? request.scene.target_object : request.object;
  robot::Scene scene = request.scene;
  scene.target_object = name;
  scene.target_pose = request.object_pose
                          ? *request.object_pose
                          : robot::targetPose(scene, world.object(name)->geometry.mesh_vertices);
  return scene;
}

/// The largest fingertip-to-contact distance a plan may have: the
/// request's max_fingertip_error, else its default for the world's robot
/// (plannerParameters: the robot's planner_defaults over the planner's).
inline double maxFingertipError(const planner::PlanningWorld& world,
                                const planner::PlanRequest& request) {
  const std::string name = "max_fingertip_error";
  if (const auto it = request.parameters.find(name); it != request.parameters.end())
    return std::stod(it->second);
  for (const planner::PlannerParameterInfo& p : planner::plannerParameters(world))
    if (p.name == name) return std::stod(p.default_value);
  ADD_FAILURE() << name << " is not a declared planner parameter";
  return 0.0;
}

/// PlannedGrasp::epsilon_at_fingertips recomputed in the world frame:
/// every fingertip of the plan's last configuration moved to the nearest
/// point of the object's mesh (Embree's nearest-point query), with the mean
/// normal of the triangles within 1e-9 m of it, on the side of the nearest
/// planned contact's normal.
inline double epsilonAtFingertips(const planner::PlanningWorld& world, const robot::Scene& scene,
                                  const planner::PlanResult& result) {
  const robot::RobotModel& robot = world.robot();
  const db::ObjectGeometry& g = world.object(scene.target_object)->geometry;
  TriangleMesh mesh;
  mesh.vertices = g.mesh_vertices;
  mesh.triangles = g.mesh_triangles;
  const db::TriangleBvh bvh(mesh);
  const robot::FingertipFrames tips =
      robot::fingertipFrames(robot, robot::forwardKinematics(robot, result.path.back()));
  grasp::GraspQualityRequest q;
  q.positions.resize(3, tips.positions.cols());
  q.normals.resize(3, tips.positions.cols());
  for (Eigen::Index f = 0; f < tips.positions.cols(); ++f) {
    const Eigen::Vector3d tip =
        scene.target_pose.inverse() * (scene.robot_base * Eigen::Vector3d(tips.positions.col(f)));
    const db::ClosestPoint nearest = bvh.closestPoint(tip);
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
      const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(t, 0)).transpose();
      const Eigen::Vector3d b = mesh.vertices.row(mesh.triangles(t, 1)).transpose();
      const Eigen::Vector3d c = mesh.vertices.row(mesh.triangles(t, 2)).transpose();
      if ((db::closestPointOnTriangle(tip, a, b, c) - tip).norm() > nearest.distance + 1e-9)
        continue;
      if ((b - a).cross(c - a).norm() > 0.0) normal += (b - a).cross(c - a).normalized();
    }
    const Eigen::Vector3d onMesh = scene.target_pose * nearest.point;
    Eigen::Index planned = 0;
    (result.grasp.contacts_world.colwise() - onMesh).colwise().squaredNorm().minCoeff(&planned);
    Eigen::Vector3d inward = result.grasp.inward_normals_world.col(planned);
    if (normal.norm() > 1e-9) {
      const Eigen::Vector3d along = scene.target_pose.linear() * -normal.normalized();
      inward = along.dot(inward) < 0.0 ? Eigen::Vector3d(-along) : along;
    }
    q.positions.col(f) = onMesh;
    q.normals.col(f) = inward;
  }
  q.center = scene.target_pose * g.center_of_mass;
  q.torque_scale = g.rho;
  q.torsional_friction = robot.torsionalFriction();
  return grasp::graspQuality(q).epsilon;
}

/// A fresh collision checker at `resolution` (the planner promises its
/// final resolution; a graze shallower than a sample step can hide between
/// samples at any resolution, see docs/planning.md), the start, the joint
/// limits, the closing motion under the grasp-aware rule, the fingertips
/// on the contacts (maxFingertipError) and a stable grasp (epsilon recomputed from the
/// world-frame contacts).
inline void expectValidPlan(const planner::PlanningWorld& world,
                            const planner::PlanRequest& request, const planner::PlanResult& result,
                            double resolution) {
  using namespace robot;
  using namespace grasp;
  using namespace planner;
  ASSERT_TRUE(result.success) << result.message;
  const RobotModel& robot = world.robot();
  const Scene scene = plannedScene(world, request);
  const db::ObjectDatabase& object = *world.object(scene.target_object);
  EXPECT_TRUE(result.object_pose.isApprox(scene.target_pose, 1e-12));
  CollisionChecker checker(robot, scene, &object.geometry);
  ASSERT_GE(result.path.size(), 2u);
  EXPECT_EQ(result.joint_names, robot.dofNames());
  EXPECT_TRUE(result.path.front().isApprox(
      request.start.value_or(scene.startFor(robot.name()).value_or(robot.home())), 1e-12));
  for (const Eigen::VectorXd& q : result.path) EXPECT_TRUE(robot.withinLimits(q));
  for (std::size_t i = 1; i + 1 < result.path.size(); ++i)
    EXPECT_TRUE(checker.isMotionValid(result.path[i - 1], result.path[i], resolution))
        << "segment " << i << " collides";
  const Eigen::VectorXd& pregrasp = result.path[result.path.size() - 2];
  const Eigen::VectorXd& grasp = result.path.back();
  EXPECT_TRUE(checker.isMotionValid(pregrasp, grasp, resolution, /*allowFingertipContact=*/true));
  EXPECT_TRUE(grasp.tail(robot.numHandDofs()).isApprox(result.grasp.hand_configuration));

  // Some finger on each contact.
  const FingertipFrames tips = fingertipFrames(robot, forwardKinematics(robot, grasp));
  const Eigen::Matrix3Xd contacts = scene.robot_base.inverse() * result.grasp.contacts_world;
  for (Eigen::Index c = 0; c < contacts.cols(); ++c) {
    double nearest = 1e9;
    for (Eigen::Index f = 0; f < tips.positions.cols(); ++f)
      nearest = std::min(nearest, (tips.positions.col(f) - contacts.col(c)).norm());
    EXPECT_LE(nearest, maxFingertipError(world, request) + 1e-9) << "contact " << c;
  }
  GraspQualityRequest q;
  q.positions = result.grasp.contacts_world;
  q.normals = result.grasp.inward_normals_world;
  q.center = scene.target_pose * object.geometry.center_of_mass;
  q.torque_scale = object.geometry.rho;
  const double epsilon = graspQuality(q).epsilon;
  EXPECT_GT(epsilon, 0.0);
  EXPECT_NEAR(epsilon, result.grasp.epsilon, 1e-9);
  EXPECT_NEAR(epsilonAtFingertips(world, scene, result), result.grasp.epsilon_at_fingertips, 1e-9);
}

/// Threads of this process (Linux: /proc/self/status), to see that a
/// planner joined what it started.
inline int processThreadCount() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("Threads:", 0) == 0) return std::stoi(line.substr(8));
  return -1;
}

}  // namespace hfts::test
