#include "plan_problem.h"

#include <iomanip>
#include <sstream>

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

/// Whether the target intersects an obstacle where it stands (kNone: not).
std::pair<PlanFailure, std::string> checkTarget(Problem& p) {
  robot::CollisionPair pair;
  if (p.checker.targetTouchesObstacles(&pair))
    return {PlanFailure::kObjectInCollision,
            "the target object intersects " + pair.second + " in this scene"};
  return {PlanFailure::kNone, ""};
}

/// Why planning cannot start in this scene (kNone: it can): checkTarget,
/// then the start configuration.
std::pair<PlanFailure, std::string> checkScene(Problem& p) {
  if (auto why = checkTarget(p); why.first != PlanFailure::kNone) return why;
  robot::CollisionPair pair;
  if (p.checker.inCollision(p.start, &pair))
    return {PlanFailure::kStartInCollision,
            "the start configuration is in collision: " + pair.first + " touches " + pair.second};
  return {PlanFailure::kNone, ""};
}

/// Why no grasp can be stable where the object stands (kNone: one may be).
std::pair<PlanFailure, std::string> checkGraspable(const Problem& p) {
  if (p.usable.empty() || grasp::stableGraspPossible(p.space, p.parameters.goals.objective))
    return {PlanFailure::kNone, ""};
  std::ostringstream why;
  why << "no stable grasp is possible with the " << p.space.usableContacts() << " of the object's "
      << p.object.numContacts() << " contacts that a fingertip (pad radius " << std::setprecision(3)
      << 1000.0 * p.world.padRadius()
      << " mm) can touch clear of the support and the other obstacles";
  return {PlanFailure::kNoStableGraspClearOfSupport, why.str()};
}

/// The time limit (counted from `began`) or the cancel flag.
ob::PlannerTerminationCondition terminationCondition(double timeLimit,
                                                     std::chrono::steady_clock::time_point began,
                                                     const std::atomic<bool>* cancel) {
  const double spent =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  return ob::plannerOrTerminationCondition(
      ob::timedPlannerTerminationCondition(std::max(0.0, timeLimit - spent)),
      ob::PlannerTerminationCondition(
          [cancel] { return cancel != nullptr && cancel->load(std::memory_order_relaxed); }));
}

}  // namespace hfts::planner
