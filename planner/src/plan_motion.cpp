#include "plan_motion.h"

#include <ompl/base/ProblemDefinition.h>

#include <algorithm>
#include <memory>
#include <utility>
#include <vector>

#include "core/invalid_argument.h"
#include "motion_goal_sampler.h"
#include "plan_diagnosis.h"
#include "plan_problem.h"
#include "racing.h"
#include "robot/sensed_scene.h"

namespace hfts::planner {

namespace {

/// What every search of one motion request shares, read-only.
struct SharedMotion {
  const PlanningWorld& world;
  const PlanSettings settings;
  const robot::Scene scene;
  const std::vector<MotionGoal> goals;  ///< checked and completed
  const Eigen::VectorXd start;
  const std::shared_ptr<const robot::CollisionScene> collision;
  /// Every goal keeps the start's hand posture: the search holds the hand
  /// there and samples the arm only.
  const bool hold_hand;
};

/// Whether every goal (checked) keeps the hand posture of `start`.
bool goalsKeepTheHand(const robot::RobotModel& robot, const std::vector<MotionGoal>& goals,
                      const Eigen::VectorXd& start) {
  const Eigen::Index hand = robot.numHandDofs();
  return std::all_of(goals.begin(), goals.end(), [&](const MotionGoal& goal) {
    const auto* joint = std::get_if<JointGoal>(&goal);
    return joint == nullptr || joint->configuration.tail(hand) == start.tail(hand);
  });
}

/// The search's space information; with hold_hand the hand's bounds are
/// the start's posture (before the planner reads them).
ob::SpaceInformationPtr searchSpace(const SharedMotion& shared, robot::CollisionChecker& checker) {
  const robot::RobotModel& robot = shared.world.robot();
  ob::SpaceInformationPtr si = makeSpaceInformation(robot, checker, kTreeResolution);
  if (!shared.hold_hand) return si;
  WeightedStateSpace& space = weightedSpace(si);
  ob::RealVectorBounds bounds = space.getBounds();
  for (int d = robot.numArmDofs(); d < robot.numDofs(); ++d) {
    bounds.setLow(static_cast<unsigned>(d), shared.start(d));
    bounds.setHigh(static_cast<unsigned>(d), shared.start(d));
  }
  space.setBounds(bounds);
  return si;
}

/// One search: its checker, space information and planner.
struct MotionSearch {
  MotionSearch(const SharedMotion& shared, std::uint64_t seedOfSearch)
      : seed(seedOfSearch),
        checker(shared.collision),
        si(searchSpace(shared, checker)),
        planner(Problem::plannerFor(si, shared.settings)) {
    checker.setSphereTier(shared.settings.execution.sphere_tier);
    planner->setCertification(shared.settings.path.certify ? &shared.world.motionBound() : nullptr);
    planner->setLastSegmentRule(robot::CertifyRule::kTransit);
  }

  const std::uint64_t seed;
  robot::CollisionChecker checker;
  const ob::SpaceInformationPtr si;
  const std::shared_ptr<MultiTreeCBiRRT> planner;
};

/// Why a motion search found nothing.
std::pair<PlanFailure, std::string> motionFailure(const GoalSamplerStatistics& goals,
                                                  std::size_t colliding,
                                                  const std::atomic<bool>* cancel) {
  if (cancel != nullptr && cancel->load()) return {PlanFailure::kCancelled, "cancelled"};
  if (goals.valid_goals == 0) {
    std::string why = "no collision-free goal configuration within the time limit";
    if (colliding > 0) why += "; " + std::to_string(colliding) + " joint goals collide";
    if (goals.rejected.no_arm_ik > 0)
      why += "; " + std::to_string(goals.rejected.no_arm_ik) + " pose draws without an IK solution";
    if (goals.rejected.colliding > 0)
      why += "; " + std::to_string(goals.rejected.colliding) + " IK solutions collide";
    return {PlanFailure::kNoValidGoal, why};
  }
  return {PlanFailure::kTimeLimit, "no path to any of the " + std::to_string(goals.valid_goals) +
                                       " goal configurations found within the time limit"};
}

PlanResult search(std::chrono::steady_clock::time_point began, const SharedMotion& shared,
                  const PlanRequest& request, MotionSearch& s, const std::atomic<bool>* cancel,
                  PlanResult result) {
  result.seed = s.seed;
  MultiTreeCBiRRT& planner = *s.planner;
  planner.setSeed(s.seed);
  MotionGoalSampler sampler(shared.world.ik(), s.checker, planner.rng(), shared.scene.robot_base,
                            shared.goals, shared.start);
  robot::CollisionPair pair;
  const std::size_t colliding = sampler.collidingJointGoals(&pair);
  if (colliding == shared.goals.size())
    return failed(
        std::move(result),
        {PlanFailure::kGoalInCollision,
         shared.collision->clearance() > 0.0
             ? "every goal collides or is within the clearance (" +
                   std::to_string(shared.collision->clearance()) + " m): the first, " + pair.first +
                   " is nearer to " + pair.second
             : "every goal collides: the first, " + pair.first + " touches " + pair.second});
  auto pdef = std::make_shared<ob::ProblemDefinition>(s.si);
  ob::ScopedState<> startState(s.si);
  weightedSpace(s.si).fromVector(shared.start, startState.get());
  pdef->addStartState(startState);
  pdef->setGoal(std::make_shared<GraspGoal>(s.si, sampler));
  planner.setProblemDefinition(pdef);
  planner.setup();
  const ob::PlannerTerminationCondition ptc =
      terminationCondition(request.time_limit, began, cancel);
  const bool solved = planner.solve(ptc) == ob::PlannerStatus::EXACT_SOLUTION;
  result.stats =
      planStatistics(planner.statistics(), sampler.statistics(), 0, s.checker.checkCount());
  if (!solved)
    return failed(std::move(result), motionFailure(sampler.statistics(), colliding, cancel));
  result.success = true;
  result.path = planner.solutionPath();
  result.clearance = planner.pathCheck().clearance;
  result.reached_goal = sampler.goalOf(result.path.back());
  if (request.trajectory_rate > 0.0 && shared.world.robot().maxAccelerations().size() > 0) {
    std::size_t queries = 0;
    result.trajectory = motionTrajectory(result.path, s.checker, planner.smoothing().final_check,
                                         request.trajectory_rate, &queries);
    result.stats.certificate_queries += queries;
  }
  return result;
}

}  // namespace

PlanResult planMotion(std::chrono::steady_clock::time_point began, const PlanningWorld& world,
                      const PlanRequest& request, const std::atomic<bool>* cancel) {
  quietOmpl();
  if (request.algorithm == PlanAlgorithm::kRrtConnect)
    throw InvalidArgument("algorithm",
                          "rrtconnect plans grasps only; motion goals are planned by the "
                          "multi-tree planner (coupled)");
  checkLimits(request);
  PlanResult result;
  result.seed = request.seed;
  result.joint_names = world.robot().dofNames();
  const Eigen::VectorXd start = startOf(world.robot(), request);
  std::vector<MotionGoal> goals = checkGoals(world.robot(), request.goals, start);
  // The object, when the request names one, is an obstacle where it stands;
  // sensed obstacles lose what the sensor saw of the robot (and the object).
  robot::Scene scene;
  const std::string name = objectNameOf(request);
  const db::ObjectDatabase* object = name.empty() ? nullptr : world.object(name);
  if (!name.empty() && object == nullptr)
    return failed(std::move(result),
                  {PlanFailure::kUnknownObject, "unknown object '" + name + "'"});
  if (object != nullptr) {
    scene = SharedProblem::sceneOf(request, *object, world.robot());
    result.object_pose = scene.target_pose;
  } else {
    scene = robot::withRobotCarved(request.scene, world.robot(), start);
  }
  const bool holdHand = goalsKeepTheHand(world.robot(), goals, start);
  PlanSettings settings = resolveSettings(world.robot(), request);
  const double clearance = settings.path.clearance;
  const SharedMotion shared{
      world,
      std::move(settings),
      scene,
      std::move(goals),
      start,
      std::make_shared<const robot::CollisionScene>(
          world.collisionModel(), scene, object != nullptr ? &object->geometry : nullptr,
          object != nullptr ? world.collisionMesh(name) : nullptr,
          object != nullptr ? world.surface(name) : nullptr, clearance),
      holdHand};
  MotionSearch first(shared, request.seed);
  if (auto why = checkStart(first.checker, start); why.first != PlanFailure::kNone)
    return failed(std::move(result), std::move(why));
  const int copies = shared.settings.execution.threads;
  if (copies == 1) return search(began, shared, request, first, cancel, result);
  return race(request.seed, cancel, copies,
              [&](int copy, std::uint64_t seed, const std::atomic<bool>* stop) {
                if (copy == 0) return search(began, shared, request, first, stop, result);
                MotionSearch other(shared, seed);
                return search(began, shared, request, other, stop, result);
              });
}

}  // namespace hfts::planner
