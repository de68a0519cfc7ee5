#pragma once
// The planning tests' world and requests, and what every returned plan
// promises, checked independently of the planner that made it.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>

#include "bundled_objects.h"
#include "grasp/grasp_quality.h"
#include "hfts_db/triangle_bvh.h"
#include "planner/grasp_motion_planner.h"
#include "planner/lift.h"
#include "robot/collision_checker.h"
#include "robot/kinematics.h"
#include "robot/link_spheres.h"
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

/// A request in a bundled scene (objects/scenes/<scene>.json), 120 s limit
/// (times sanitizerSlowdown()): far above what the tests' plans take on a
/// free machine (under 10 s with the physics check), so that a slow or
/// loaded machine changes no verdict; a plan that succeeds returns at once.
inline planner::PlanRequest bundledSceneRequest(const std::string& scene, const std::string& object,
                                                std::uint64_t seed,
                                                planner::PlanAlgorithm algorithm) {
  planner::PlanRequest r;
  r.scene = robot::loadScene(sourcePath("objects/scenes/" + scene + ".json"));
  r.object = object;
  r.seed = seed;
  r.algorithm = algorithm;
  r.time_limit = 120.0 * sanitizerSlowdown();
  return r;
}

/// The table scene without obstacles and the mug 3 m away, beyond the ball
/// that bounds the fingertips' reach: refused before any search (1 s limit).
inline planner::PlanRequest outOfReachRequest(planner::PlanAlgorithm algorithm) {
  planner::PlanRequest r = bundledSceneRequest("table", "mug", 1, algorithm);
  r.scene.obstacles.clear();
  r.object_pose = Eigen::Isometry3d(Eigen::Translation3d(3.0, 0.0, 0.0));
  r.time_limit = 1.0;
  return r;
}

/// The same with the mug 1.3 m in front of the KR5's shoulder: inside the
/// reach ball, beyond what the arm reaches (about 1.2 m): no grasp has an
/// arm IK solution, found by searching.
inline planner::PlanRequest justOutOfReachRequest(planner::PlanAlgorithm algorithm) {
  planner::PlanRequest r = outOfReachRequest(algorithm);
  r.object_pose = Eigen::Isometry3d(Eigen::Translation3d(1.3, 0.0, 0.335));
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
/// A planner parameter's value in a request, else its default.
inline double parameterOf(const planner::PlanningWorld& world, const planner::PlanRequest& request,
                          const std::string& name) {
  if (const auto it = request.parameters.find(name); it != request.parameters.end())
    return std::stod(it->second);
  for (const planner::PlannerParameterInfo& p : planner::plannerParameters(world))
    if (p.name == name) return std::stod(p.default_value);
  ADD_FAILURE() << name << " is not a declared planner parameter";
  return 0.0;
}

inline double maxFingertipError(const planner::PlanningWorld& world,
                                const planner::PlanRequest& request) {
  return parameterOf(world, request, "max_fingertip_error");
}

inline double maxPenetration(const planner::PlanningWorld& world,
                             const planner::PlanRequest& request) {
  return parameterOf(world, request, "max_penetration");
}

/// The lift of a plan asked for one (PlanRequest::lift): from the grasp,
/// the hand as closed, the palm on a straight line of the height asked, out
/// from under something (up, aside, up) or planned (LiftPath::direction),
/// every segment free at `resolution` for the robot holding the object
/// (the object too, against the obstacles and the arm), the object clear
/// of every obstacle at the end.
inline void expectValidLift(const planner::PlanningWorld& world,
                            const planner::PlanRequest& request, const planner::PlanResult& result,
                            const robot::Scene& scene, const db::ObjectDatabase& object,
                            double resolution) {
  using namespace robot;
  if (!request.lift || !request.goals.empty()) {
    EXPECT_FALSE(result.lift.has_value());
    return;
  }
  ASSERT_TRUE(result.lift.has_value());
  const std::vector<Eigen::VectorXd>& lift = result.lift->path;
  ASSERT_GE(lift.size(), 2u);
  const RobotModel& robot = world.robot();
  const Eigen::VectorXd& grasp = result.path.back();
  EXPECT_TRUE(lift.front().isApprox(grasp, 1e-12));
  const planner::Hold hold =
      planner::holdObject(world.collisionModel(), scene.robot_base, object.geometry, object.name,
                          scene.target_pose, grasp);
  Scene obstacles = scene;
  obstacles.target_object.clear();
  CollisionChecker held(*hold.model, obstacles, nullptr);
  EXPECT_FALSE(held.inCollision(lift.front()));
  for (std::size_t i = 1; i < lift.size(); ++i) {
    EXPECT_TRUE(robot.withinLimits(lift[i]));
    EXPECT_TRUE(lift[i].tail(robot.numHandDofs()).isApprox(grasp.tail(robot.numHandDofs())));
    EXPECT_TRUE(held.isMotionValid(lift[i - 1], lift[i], resolution)) << "lift segment " << i;
  }
  const auto palmAt = [&](const Eigen::VectorXd& q) {
    return scene.robot_base *
           forwardKinematics(robot, q)[static_cast<std::size_t>(robot.palmLink())];
  };
  const Eigen::Isometry3d from = palmAt(lift.front()), to = palmAt(lift.back());
  const Eigen::Vector3d moved = to.translation() - from.translation();
  const double height = request.lift->height;
  const std::string& direction = result.lift->direction;
  if (direction == "planned") {
    // Rises by the height at least, turned 20 degrees at most.
    EXPECT_GT(moved.z(), height - 1e-3);
    EXPECT_LT(Eigen::AngleAxisd(from.linear().transpose() * to.linear()).angle(),
              20.0 * M_PI / 180.0 + 1e-3);
    return;
  }
  EXPECT_TRUE(to.linear().isApprox(from.linear(), 1e-4));
  if (direction.rfind("out_", 0) == 0) {
    // 1 cm up, 0.1, 0.2 or 0.3 m aside, up the rest of the height.
    EXPECT_NEAR(moved.z(), height, 1e-3);
    const double aside = moved.head<2>().norm();
    EXPECT_NEAR(aside, 0.1 * std::round(aside / 0.1), 1e-3);
    EXPECT_GE(std::round(aside / 0.1), 1.0);
    EXPECT_LE(std::round(aside / 0.1), 3.0);
    return;
  }
  EXPECT_NEAR(moved.norm(), height, 1e-3);
  if (direction != "retreat") {
    EXPECT_GT(moved.z(), 0.5 * height);
  }
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
  CollisionChecker checker(world.collisionModel(), scene, &object.geometry);
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
  EXPECT_TRUE(checker.isMotionValid(pregrasp, grasp, resolution, robot::CollisionRequest::grasp()));
  EXPECT_TRUE(grasp.tail(robot.numHandDofs()).isApprox(result.grasp.hand_configuration));

  // The grasp as executed: each fingertip link touches the object's
  // surface at its contact (within the closing's contact distance), the
  // contact lies on the mesh, and epsilon there is the plan's.
  const LinkPoses poses = forwardKinematics(robot, grasp);
  TriangleMesh mesh{object.geometry.mesh_vertices, object.geometry.mesh_triangles};
  const db::TriangleBvh bvh(mesh);
  // grasp::FingerClosure::contact: within twice the contact distance.
  constexpr double kTouch = 2 * 1e-4 + 1e-6;
  ASSERT_EQ(result.grasp.contacts_world.cols(),
            static_cast<Eigen::Index>(robot.fingertips().size()));
  for (std::size_t f = 0; f < robot.fingertips().size(); ++f) {
    const auto c = static_cast<Eigen::Index>(f);
    const Eigen::Vector3d contact = result.grasp.contacts_world.col(c);
    EXPECT_LE(bvh.closestPoint(scene.target_pose.inverse() * contact).distance, 1e-9)
        << "contact " << f << " is not on the mesh";
    const int link = robot.fingertips()[f].link;
    const Eigen::Vector3d inLink =
        (scene.robot_base * poses[static_cast<std::size_t>(link)]).inverse() * contact;
    EXPECT_LE(signedDistance(robot.links()[static_cast<std::size_t>(link)], inLink), kTouch)
        << "fingertip " << f << " does not touch its contact";
  }
  EXPECT_LE(result.grasp.penetration, maxPenetration(world, request) + 1e-12);
  GraspQualityRequest q;
  q.positions = result.grasp.contacts_world;
  q.normals = result.grasp.inward_normals_world;
  q.center = scene.target_pose * object.geometry.center_of_mass;
  q.torque_scale = object.geometry.rho;
  q.torsional_friction = robot.torsionalFriction();
  const double epsilon = graspQuality(q).epsilon;
  EXPECT_GT(epsilon, 0.0);
  EXPECT_GE(epsilon, parameterOf(world, request, "min_epsilon") - 1e-12);
  EXPECT_NEAR(epsilon, result.grasp.epsilon, 1e-9);
  // The planned fingertips were near the planned contacts (the search's filter).
  EXPECT_LE(result.grasp.fingertip_error, maxFingertipError(world, request) + 1e-9);
  expectValidLift(world, request, result, scene, object, resolution);
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
