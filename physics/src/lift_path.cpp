// Straight palm lines by damped least squares, and the choice of the lift.
#include "physics/lift_path.h"

#include <cmath>

#include "hfts_db/invalid_argument.h"
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

LiftPlan planLift(const robot::RobotModel& robot, const robot::Scene& scene,
                  const Eigen::VectorXd& grasp, double height) {
  robot::CollisionChecker checker(robot, scene, nullptr);
  LiftPlan up{
      "up", straightPalmLine(robot, scene.robot_base, grasp, Eigen::Vector3d::UnitZ(), height), {}};
  std::string upProblem = up.line.problem;
  if (upProblem.empty()) upProblem = firstCollision(checker, up.line);
  if (upProblem.empty()) return up;
  const Eigen::Isometry3d palm =
      scene.robot_base *
      robot::forwardKinematics(robot, grasp)[static_cast<std::size_t>(robot.palmLink())];
  LiftPlan back{"retreat",
                straightPalmLine(robot, scene.robot_base, grasp, -palm.linear().col(2), height),
                {}};
  if (back.line.problem.empty() && firstCollision(checker, back.line).empty()) return back;
  up.direction = "up_blocked";
  up.blocked_by = upProblem;
  return up;
}

}  // namespace hfts::physics
