#include "planner/grasp_motion_planner.h"

#include <chrono>
#include <cmath>
#include <utility>
#include <vector>

#include "core/invalid_argument.h"
#include "plan_diagnosis.h"
#include "plan_problem.h"
#include "plan_search.h"
#include "racing.h"

namespace hfts::planner {

namespace {

/// What validating a successful plan checks, with the request's criteria
/// (defined with validatePlan).
ValidationRequest validationRequest(const PlanningWorld& world, const PlanRequest& request,
                                    const PlanResult& plan);

/// planGrasp without the planning time, which counts the teardown of
/// everything this builds (trees, caches, checkers, the sampling thread).
PlanResult planFrom(std::chrono::steady_clock::time_point began, const PlanningWorld& world,
                    const PlanRequest& request, const std::atomic<bool>* cancel) {
  quietOmpl();
  PlanResult result;
  result.seed = request.seed;
  result.joint_names = world.robot().dofNames();
  result.object_pose = request.object_pose.value_or(request.scene.target_pose);
  Eigen::VectorXd start = startOf(world.robot(), request);
  if (!(request.time_limit >= 0.0) || !std::isfinite(request.time_limit))
    throw InvalidArgument("time_limit", "must be a finite number >= 0");
  if (!(request.trajectory_rate >= 0.0 && request.trajectory_rate <= kMaxTrajectoryRate))
    throw InvalidArgument("trajectory_rate", "must be in [0, 1000] (samples per second)");
  const std::string name = objectNameOf(request);
  const db::ObjectDatabase* object = world.object(name);
  if (object == nullptr)
    return failed(std::move(result),
                  {PlanFailure::kUnknownObject, "unknown object '" + name + "'"});

  Problem problem(world, *object, request, std::move(start));
  result.object_pose = problem.scene.target_pose;
  if (auto why = checkScene(problem); why.first != PlanFailure::kNone)
    return failed(std::move(result), std::move(why));
  if (auto why = checkGraspable(problem); why.first != PlanFailure::kNone)
    return failed(std::move(result), std::move(why));
  const ob::PlannerTerminationCondition ptc =
      terminationCondition(request.time_limit, began, cancel);
  SearchOutcome found =
      request.algorithm == PlanAlgorithm::kRrtConnect
          ? searchBaseline(problem, ptc)
          : searchMultiTree(problem, request.algorithm == PlanAlgorithm::kCoupled, ptc);
  result.stats = found.stats;
  result.explored = std::move(found.explored);
  if (!found.solved) return failed(std::move(result), failureOf(found, cancel));
  result.success = true;
  result.path = std::move(found.path);
  result.path.push_back(found.goal.grasp);
  result.grasp = describeGrasp(problem, found.goal);
  if (found.verdict) {
    // The search simulated this grasp already: the same verdict.
    ValidationRequest v = validationRequest(world, request, result);
    v.physics = false;
    result.validation = validateGrasp(world, v);
    result.validation->physics = std::move(found.verdict);
  }
  if (request.trajectory_rate > 0.0 && world.robot().maxAccelerations().size() > 0)
    result.trajectory =
        graspTrajectory(result.path, problem.checker, problem.settings.execution.final_resolution,
                        request.trajectory_rate);
  return result;
}

}  // namespace

std::vector<PlannerParameterInfo> plannerParameters(const PlanningWorld& world) {
  return describeSettings(defaultSettings(world.robot()), world.robot());
}

PlanResult planGrasp(const PlanningWorld& world, const PlanRequest& request,
                     const std::atomic<bool>* cancel) {
  const auto began = std::chrono::steady_clock::now();
  if (request.validate) physics::validateOptions(request.simulation);
  const int copies = resolveSettings(world.robot(), request).execution.threads;
  PlanResult result = copies == 1
                          ? planFrom(began, world, request, cancel)
                          : race(request, cancel, copies,
                                 [&](const PlanRequest& copy, const std::atomic<bool>* stop) {
                                   return planFrom(began, world, copy, stop);
                                 });
  result.stats.planning_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  if (request.validate && result.success && !result.validation)
    result.validation = validatePlan(world, request, result);
  return result;
}

Validation validatePlan(const PlanningWorld& world, const PlanRequest& request,
                        const PlanResult& plan) {
  if (!plan.success || plan.path.size() < 2)
    throw InvalidArgument("plan", "only a successful plan has a grasp to validate");
  return validateGrasp(world, validationRequest(world, request, plan));
}

namespace {

ValidationRequest validationRequest(const PlanningWorld& world, const PlanRequest& request,
                                    const PlanResult& plan) {
  ValidationRequest v;
  v.scene = request.scene;
  v.scene.target_object = objectNameOf(request);
  v.scene.target_pose = plan.object_pose;
  v.scene.target_rest_on.clear();
  v.pregrasp = plan.path[plan.path.size() - 2];
  v.grasp = plan.path.back();
  v.simulation = request.simulation;
  // The request's criteria, as the planner read them.
  const PlanSettings settings = resolveSettings(world.robot(), request);
  v.check.min_epsilon = settings.goal.min_epsilon;
  v.check.max_penetration = settings.goal.max_penetration;
  v.check.resolution = settings.execution.final_resolution;
  v.check.friction = settings.paper.friction;
  return v;
}

}  // namespace

}  // namespace hfts::planner
