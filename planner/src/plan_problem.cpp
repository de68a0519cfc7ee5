#include "plan_problem.h"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "robot/kinematics.h"
#include "robot/object_surface.h"

namespace hfts::planner {

Eigen::VectorXd startOf(const robot::RobotModel& robot, const PlanRequest& request) {
  const Eigen::VectorXd start =
      request.start ? *request.start : request.scene.startFor(robot.name()).value_or(robot.home());
  if (start.size() != robot.numDofs())
    throw InvalidArgument("start", std::to_string(robot.numDofs()) + " values expected, got " +
                                       std::to_string(start.size()));
  if (!start.allFinite()) throw InvalidArgument("start", "values must be finite");
  std::string which;
  if (!robot.withinLimits(start, 1e-9, &which)) throw InvalidArgument("start", which);
  return start;
}

/// The request's object: `object`, else the scene's target.
std::string objectNameOf(const PlanRequest& request) {
  return request.object.empty() ? request.scene.target_object : request.object;
}

void checkLimits(const PlanRequest& request) {
  if (!(request.time_limit >= 0.0) || !std::isfinite(request.time_limit))
    throw InvalidArgument("time_limit", "must be a finite number >= 0");
  if (!(request.trajectory_rate >= 0.0 && request.trajectory_rate <= kMaxTrajectoryRate))
    throw InvalidArgument("trajectory_rate", "must be in [0, 1000] (samples per second)");
}

std::pair<PlanFailure, std::string> checkStart(robot::CollisionChecker& checker,
                                               const Eigen::VectorXd& start) {
  robot::CollisionPair pair;
  robot::CollisionRequest strict;
  strict.clearance = false;
  if (checker.inCollision(start, strict, &pair))
    return {PlanFailure::kStartInCollision,
            "the start configuration is in collision: " + pair.first + " touches " + pair.second};
  if (checker.scene().clearance() > 0.0 && checker.inCollision(start, &pair))
    return {PlanFailure::kStartInCollision,
            "the start configuration is within the clearance (" +
                std::to_string(checker.scene().clearance()) + " m) of something: " + pair.first +
                " is nearer to " + pair.second + "; lower the parameter clearance"};
  return {PlanFailure::kNone, ""};
}

/// Whether the target intersects an obstacle where it stands (kNone: not).
std::pair<PlanFailure, std::string> checkTarget(Problem& p) {
  robot::CollisionPair pair;
  if (p.checker.scene().targetTouchesObstacles(&pair))
    return {PlanFailure::kObjectInCollision,
            "the target object intersects " + pair.second + " in this scene"};
  return {PlanFailure::kNone, ""};
}

std::pair<PlanFailure, std::string> checkReach(const Problem& p) {
  const robot::ObjectSurface* surface = p.world.surface(p.object.name);
  if (surface == nullptr) return {PlanFailure::kNone, ""};
  const robot::ReachBall reach = robot::fingertipReach(p.world.robot());
  const Eigen::Vector3d centre = p.scene.target_pose.inverse() * p.scene.robot_base * reach.centre;
  const double distance = surface->nearest(centre).signed_distance;
  if (distance <= reach.radius + p.world.padRadius()) return {PlanFailure::kNone, ""};
  std::ostringstream why;
  why << std::fixed << std::setprecision(3) << "the object is out of reach: its surface is "
      << distance << " m from the arm's first joint, and no fingertip reaches farther than "
      << reach.radius + p.world.padRadius() << " m from it";
  return {PlanFailure::kObjectUnreachable, why.str()};
}

/// Why planning cannot start in this scene (kNone: it can): checkTarget,
/// checkReach, then the start configuration.
std::pair<PlanFailure, std::string> checkScene(Problem& p) {
  if (auto why = checkTarget(p); why.first != PlanFailure::kNone) return why;
  if (auto why = checkReach(p); why.first != PlanFailure::kNone) return why;
  return checkStart(p.checker, p.start);
}

/// Why no grasp can be stable where the object stands (kNone: one may be).
std::pair<PlanFailure, std::string> checkGraspable(const Problem& p) {
  if (p.usable.empty() || grasp::stableGraspPossible(p.space, p.goals.objective))
    return {PlanFailure::kNone, ""};
  std::ostringstream why;
  why << "no stable grasp is possible with the " << p.space.usableContacts() << " of the object's "
      << p.object.numContacts() << " contacts that a fingertip (pad radius " << std::setprecision(3)
      << 1000.0 * p.world.padRadius()
      << " mm) can touch clear of the support and the other obstacles";
  return {PlanFailure::kNoStableGraspClearOfSupport, why.str()};
}

ob::PlannerTerminationCondition terminationCondition(double timeLimit,
                                                     std::chrono::steady_clock::time_point began,
                                                     const std::atomic<bool>* cancel) {
  const double spent =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  return ob::plannerOrTerminationCondition(
      ob::timedPlannerTerminationCondition(std::max(0.0, searchTimeLimit(timeLimit) - spent)),
      ob::PlannerTerminationCondition(
          [cancel] { return cancel != nullptr && cancel->load(std::memory_order_relaxed); }));
}

}  // namespace hfts::planner
