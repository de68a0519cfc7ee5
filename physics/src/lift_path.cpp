// Straight palm lines by damped least squares, and the choice of the lift.
#include "physics/lift_path.h"

#include <cmath>
#include <string>
#include <vector>

#include "core/invalid_argument.h"
#include "robot/collision_checker.h"
#include "robot/kinematics.h"

namespace hfts::physics {
namespace {

constexpr double kPositionTolerance = 1e-6;  // m
constexpr double kAngleTolerance = 1e-5;     // rad
constexpr int kIterations = 50;              // per waypoint; a 5 mm step needs 2-3
constexpr double kDamping = 1e-3;            // lambda of (J J^T + lambda^2 I)^-1

/// Palm pose error (translation; rotation vector) of q against `target`,
/// both in the base frame.
Eigen::Matrix<double, 6, 1> palmError(const robot::RobotModel& robot, const robot::LinkPoses& poses,
                                      const Eigen::Isometry3d& target) {
  const Eigen::Isometry3d& palm = poses[static_cast<std::size_t>(robot.palmLink())];
  Eigen::Matrix<double, 6, 1> error;
  error.head<3>() = target.translation() - palm.translation();
  const Eigen::AngleAxisd turn(target.linear() * palm.linear().transpose());
  error.tail<3>() = turn.angle() * turn.axis();
  return error;
}

/// Moves q's arm until the palm is at `target`; false when it cannot
/// (joint limits, a singularity).
bool reach(const robot::RobotModel& robot, const Eigen::Isometry3d& target, Eigen::VectorXd& q) {
  const int arm = robot.numArmDofs();
  robot::LinkPoses poses;
  for (int i = 0; i < kIterations; ++i) {
    robot::forwardKinematics(robot, q, poses);
    const Eigen::Matrix<double, 6, 1> error = palmError(robot, poses, target);
    if (error.head<3>().norm() < kPositionTolerance && error.tail<3>().norm() < kAngleTolerance)
      return true;
    const Eigen::MatrixXd j =
        robot::jacobian(robot, poses, robot.palmLink(), Eigen::Vector3d::Zero()).leftCols(arm);
    const Eigen::Matrix<double, 6, 6> jjt =
        j * j.transpose() + kDamping * kDamping * Eigen::Matrix<double, 6, 6>::Identity();
    q.head(arm) += j.transpose() * jjt.ldlt().solve(error);
    q.head(arm) =
        q.head(arm).cwiseMax(robot.lowerLimits().head(arm)).cwiseMin(robot.upperLimits().head(arm));
  }
  return false;
}

void checkLineInput(const robot::RobotModel& robot, const Eigen::VectorXd& start,
                    const Eigen::Vector3d& direction, double distance, double step) {
  std::string why;
  if (!robot.withinLimits(start, 1e-9, &why)) throw InvalidArgument("start", why);
  if (!direction.allFinite() || direction.norm() < 1e-12)
    throw InvalidArgument("direction", "must be a finite non-zero vector");
  if (!(distance > 0.0) || !std::isfinite(distance))
    throw InvalidArgument("distance", "must be a finite number > 0 (m)");
  if (!(step > 0.0) || !std::isfinite(step))
    throw InvalidArgument("step", "must be a finite number > 0 (m)");
}

/// The first waypoint that collides, as "<link> touches <obstacle>", or
/// empty when all are free.
std::string firstCollision(robot::CollisionChecker& checker, const PalmLine& line) {
  for (const Eigen::VectorXd& q : line.waypoints) {
    robot::CollisionPair pair;
    if (checker.inCollision(q, &pair)) return pair.first + " touches " + pair.second;
  }
  return {};
}

struct LiftCandidate {
  std::string name;
  Eigen::Vector3d direction;  ///< world frame
};

/// Where a lift may go, in order: straight up; straight back against the
/// palm's approach axis; up at 45 degrees towards that retreat, towards the
/// robot's base and towards the four horizontal axes (the way out of a
/// shelf or from under a lamp).
std::vector<LiftCandidate> liftCandidates(const Eigen::Isometry3d& palm,
                                          const robot::Scene& scene) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d back = -palm.linear().col(2);
  std::vector<LiftCandidate> out{{"up", up}, {"retreat", back}};
  const auto tilted = [&](const std::string& name, Eigen::Vector3d horizontal) {
    horizontal.z() = 0.0;
    if (horizontal.norm() > 1e-6) out.push_back({name, up + horizontal.normalized()});
  };
  tilted("up_retreat", back);
  tilted("up_to_base", scene.robot_base.translation() - palm.translation());
  tilted("up_x", Eigen::Vector3d::UnitX());
  tilted("up_minus_x", -Eigen::Vector3d::UnitX());
  tilted("up_y", Eigen::Vector3d::UnitY());
  tilted("up_minus_y", -Eigen::Vector3d::UnitY());
  return out;
}

/// The object carried along the palm line (its pose fixed in the palm
/// frame): where it first meets an obstacle, from its second centimetre
/// on (it starts on its support), checked every 2.5 cm and at the end;
/// empty when it meets none.
std::string objectCollision(const robot::CollisionModel& model, const robot::Scene& scene,
                            const db::ObjectGeometry& object, const PalmLine& line) {
  constexpr double kFrom = 0.01, kEvery = 0.025;
  const robot::RobotModel& robot = model.robot;
  const auto palmAt = [&](const Eigen::VectorXd& q) {
    return scene.robot_base *
           robot::forwardKinematics(robot, q)[static_cast<std::size_t>(robot.palmLink())];
  };
  const Eigen::Isometry3d start = palmAt(line.waypoints.front());
  const Eigen::Isometry3d inPalm = start.inverse() * scene.target_pose;
  double next = kFrom;
  for (std::size_t k = 1; k < line.waypoints.size(); ++k) {
    const Eigen::Isometry3d palm = palmAt(line.waypoints[k]);
    const double travelled = (palm.translation() - start.translation()).norm();
    if (travelled < next && k + 1 < line.waypoints.size()) continue;
    next = travelled + kEvery;
    robot::Scene moved = scene;
    moved.target_pose = palm * inPalm;
    robot::CollisionPair pair;
    if (robot::CollisionScene(model, moved, &object).targetTouchesObstacles(&pair))
      return "the object touches " + pair.second;
  }
  return {};
}

}  // namespace

PalmLine straightPalmLine(const robot::RobotModel& robot, const Eigen::Isometry3d& robotBase,
                          const Eigen::VectorXd& start, const Eigen::Vector3d& direction,
                          double distance, double step) {
  checkLineInput(robot, start, direction, distance, step);
  const Eigen::Vector3d along = robotBase.linear().transpose() * direction.normalized();
  const Eigen::Isometry3d palm0 =
      robot::forwardKinematics(robot, start)[static_cast<std::size_t>(robot.palmLink())];
  const int steps = static_cast<int>(std::ceil(distance / step - 1e-9));
  PalmLine line;
  line.waypoints.push_back(start);
  Eigen::VectorXd q = start;
  for (int k = 1; k <= steps; ++k) {
    Eigen::Isometry3d target = palm0;
    const double travelled = std::min(distance, k * step);
    target.translation() += travelled * along;
    if (!reach(robot, target, q)) {
      line.problem = "the palm cannot follow the line beyond " +
                     std::to_string(static_cast<int>(std::lround(1000 * (k - 1) * step))) +
                     " mm (joint limits or a singularity)";
      return line;
    }
    line.waypoints.push_back(q);
  }
  return line;
}

LiftPlan planLift(const robot::CollisionModel& model, const robot::Scene& scene,
                  const Eigen::VectorXd& grasp, double height, const db::ObjectGeometry* object) {
  const robot::RobotModel& robot = model.robot;
  robot::CollisionChecker checker(model, scene, nullptr);
  const Eigen::Isometry3d palm =
      scene.robot_base *
      robot::forwardKinematics(robot, grasp)[static_cast<std::size_t>(robot.palmLink())];
  std::string upProblem;
  for (const LiftCandidate& c : liftCandidates(palm, scene)) {
    LiftPlan plan{
        c.name, straightPalmLine(robot, scene.robot_base, grasp, c.direction, height), {}};
    std::string problem = plan.line.problem;
    if (problem.empty()) problem = firstCollision(checker, plan.line);
    if (problem.empty() && object != nullptr)
      problem = objectCollision(model, scene, *object, plan.line);
    if (problem.empty()) return plan;
    if (upProblem.empty()) upProblem = problem;  // the first candidate is up
  }
  LiftPlan up{"up_blocked",
              straightPalmLine(robot, scene.robot_base, grasp, Eigen::Vector3d::UnitZ(), height),
              upProblem};
  return up;
}

}  // namespace hfts::physics
