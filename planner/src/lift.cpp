#include "planner/lift.h"

#include <cmath>
#include <utility>

#include "core/invalid_argument.h"
#include "physics/lift_path.h"
#include "robot/kinematics.h"
#include "robot/motion_bound.h"
#include "robot/sensed_scene.h"

namespace hfts::planner {

void checkLiftOptions(const LiftOptions& options) {
  if (!(options.height > 0.0 && options.height <= 1.0))
    throw InvalidArgument("lift.height",
                          "must be in (0, 1] m, not " + std::to_string(options.height));
  if (!(options.held_speed > 0.0 && options.held_speed <= 1.0))
    throw InvalidArgument("lift.held_speed",
                          "must be in (0, 1], not " + std::to_string(options.held_speed));
}

namespace {

/// A lift's direction rises at least this much per unit of travel: at
/// most 60 degrees from up, so that the object leaves its support.
constexpr double kMinLiftRise = 0.5;

/// How far a lift that slides the object out from under something first
/// raises it (m; at most half the lift's height).
constexpr double kSlideRise = 0.01;

Eigen::Isometry3d palmPose(const robot::RobotModel& robot, const Eigen::Isometry3d& robotBase,
                           const Eigen::VectorXd& q) {
  return robotBase * robot::forwardKinematics(robot, q)[static_cast<std::size_t>(robot.palmLink())];
}

/// A checker of the robot holding the object among the scene's obstacles,
/// and `check` with the proofs' bound of that robot.
struct HeldChecker {
  HeldChecker(const Hold& hold, const robot::Scene& scene, const MotionCheck& check)
      : checker(*hold.model, robot::heldScene(scene), nullptr),
        bound(hold.model->robot),
        held(check) {
    if (held.certifies()) held.bound = &bound;
    // The object starts 1 mm above its support: like the closing motion,
    // the lift is free but keeps no clearance.
    held.clearance = 0.0;
  }
  robot::CollisionChecker checker;
  const robot::MotionBound bound;
  MotionCheck held;
};

/// The straight palm line from `from`, checked for the robot holding the
/// object (heldPalmLine).
std::optional<std::vector<Eigen::VectorXd>> heldPalmLine(
    HeldChecker& held, const robot::Scene& scene, const Eigen::VectorXd& from,
    const Eigen::Vector3d& direction, double distance, std::string* why, std::size_t* queries,
    const std::function<bool()>& stop) {
  const robot::RobotModel& robot = held.checker.model();
  const physics::PalmLine line =
      physics::straightPalmLine(robot, scene.robot_base, from, direction, distance);
  std::string blocked = line.problem;
  if (blocked.empty()) {
    const MotionVerdict verdict =
        checkMotion(held.checker, held.held, line.waypoints, robot::CertifyRule::kTransit, stop);
    if (queries != nullptr) *queries += verdict.queries;
    if (verdict.free) return line.waypoints;
    // What the samples see (a proof may fail where they see nothing).
    robot::CollisionPair pair;
    blocked = held.checker.validSegments(line.waypoints, held.held.resolution, {}, &pair) + 1 <
                      line.waypoints.size()
                  ? pair.first + " collides with " + pair.second
                  : "not proven free";
  }
  if (why != nullptr) *why = blocked;
  return std::nullopt;
}

/// Under something that blocks every lift: the object raised kSlideRise
/// off its support, slid out along one of `asides` (horizontal, named) by
/// 0.1, 0.2 or 0.3 m, then lifted the rest of the height; the first free
/// one.
std::optional<LiftPath> slideOut(HeldChecker& held, const robot::Scene& scene,
                                 const Eigen::VectorXd& grasp, double height,
                                 const std::vector<std::pair<std::string, Eigen::Vector3d>>& asides,
                                 const std::function<bool()>& stop) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const double rise = std::min(kSlideRise, height / 2.0);
  const std::optional<std::vector<Eigen::VectorXd>> raised =
      heldPalmLine(held, scene, grasp, up, rise, nullptr, nullptr, stop);
  if (!raised) return std::nullopt;
  for (const auto& [name, aside] : asides) {
    if (aside.norm() < 1e-6) continue;
    for (const double distance : {0.1, 0.2, 0.3}) {
      if (stop && stop()) return std::nullopt;
      std::optional<std::vector<Eigen::VectorXd>> slide =
          heldPalmLine(held, scene, raised->back(), aside, distance, nullptr, nullptr, stop);
      // A longer slide along the same line is blocked where this one is.
      if (!slide) break;
      std::optional<std::vector<Eigen::VectorXd>> lift =
          heldPalmLine(held, scene, slide->back(), up, height - rise, nullptr, nullptr, stop);
      if (!lift) continue;
      std::vector<Eigen::VectorXd> path = *raised;
      path.insert(path.end(), slide->begin() + 1, slide->end());
      path.insert(path.end(), lift->begin() + 1, lift->end());
      return LiftPath{std::move(path), name};
    }
  }
  return std::nullopt;
}

}  // namespace

Hold holdObject(const robot::CollisionModel& model, const Eigen::Isometry3d& robotBase,
                const db::ObjectGeometry& object, const std::string& name,
                const Eigen::Isometry3d& objectPose, const Eigen::VectorXd& grasp) {
  Hold hold;
  hold.object_in_palm = palmPose(model.robot, robotBase, grasp).inverse() * objectPose;
  auto mesh = std::make_shared<TriangleMesh>();
  mesh->vertices = object.mesh_vertices;
  mesh->triangles = object.mesh_triangles;
  hold.model =
      robot::withHeldBody(model, "held '" + name + "'", hold.object_in_palm, std::move(mesh));
  return hold;
}

std::shared_ptr<const PlanningWorld> carryWorld(const PlanningWorld& world, const Hold& hold,
                                                const Eigen::VectorXd& grasp) {
  const robot::RobotModel& robot = hold.model->robot;
  auto model = std::make_shared<robot::CollisionModel>(*hold.model);
  model->robot = robot.withHandFixed(grasp.tail(robot.numHandDofs()));
  return std::make_shared<const PlanningWorld>(std::move(model), world.objects());
}

std::optional<LiftPath> planLift(const Hold& hold, const robot::Scene& scene,
                                 const Eigen::VectorXd& grasp, double height,
                                 const MotionCheck& check, std::string* why, std::size_t* queries,
                                 const std::function<bool()>& stop) {
  checkLiftOptions({height});
  const robot::RobotModel& robot = hold.model->robot;
  // The proofs bound the held object's motion too.
  HeldChecker held(hold, scene, check);

  const Eigen::Isometry3d palm = palmPose(robot, scene.robot_base, grasp);
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d back = -palm.linear().col(2);  // against the approach axis
  Eigen::Vector3d toBase = scene.robot_base.translation() - palm.translation();
  toBase.z() = 0.0;
  std::vector<std::pair<std::string, Eigen::Vector3d>> directions{
      {"up", up}, {"up_retreat", up + back}, {"retreat", back}};
  if (toBase.norm() > 1e-6) directions.emplace_back("up_to_base", up + toBase.normalized());
  directions.insert(directions.end(), {{"up_x", up + Eigen::Vector3d::UnitX()},
                                       {"up_minus_x", up - Eigen::Vector3d::UnitX()},
                                       {"up_y", up + Eigen::Vector3d::UnitY()},
                                       {"up_minus_y", up - Eigen::Vector3d::UnitY()}});
  for (const auto& [name, direction] : directions) {
    if (stop && stop()) return std::nullopt;
    // A lift raises the object: at most 60 degrees from up.
    if (direction.norm() < 1e-6 || direction.normalized().z() < kMinLiftRise) continue;
    std::string blocked;
    if (auto line = heldPalmLine(held, scene, grasp, direction, height, &blocked, queries, stop))
      return LiftPath{std::move(*line), name};
    if (why != nullptr && name == "up") *why = "lifting up: " + blocked;
  }
  Eigen::Vector3d level = back;
  level.z() = 0.0;
  const std::vector<std::pair<std::string, Eigen::Vector3d>> asides{
      {"out_to_base", toBase},
      {"out_back", level},
      {"out_x", Eigen::Vector3d::UnitX()},
      {"out_minus_x", -Eigen::Vector3d::UnitX()},
      {"out_y", Eigen::Vector3d::UnitY()},
      {"out_minus_y", -Eigen::Vector3d::UnitY()}};
  return slideOut(held, scene, grasp, height, asides, stop);
}

std::optional<std::vector<Eigen::VectorXd>> heldPalmLine(
    const Hold& hold, const robot::Scene& scene, const Eigen::VectorXd& from,
    const Eigen::Vector3d& direction, double distance, const MotionCheck& check, std::string* why,
    std::size_t* queries, const std::function<bool()>& stop) {
  HeldChecker held(hold, scene, check);
  return heldPalmLine(held, scene, from, direction, distance, why, queries, stop);
}

GraspTrajectory liftTrajectory(const Hold& hold, const robot::Scene& scene, const LiftPath& lift,
                               const MotionCheck& check, double rate, std::size_t* queries,
                               double speed) {
  HeldChecker held(hold, scene, check);
  return motionTrajectory(lift.path, held.checker, held.held, rate, queries,
                          TrajectoryOptions{}.max_deviation, speed);
}

}  // namespace hfts::planner
