#include "planner/grasp_motion_planner.h"

#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "core/invalid_argument.h"
#include "physics/simulate_grasp.h"
#include "plan_diagnosis.h"
#include "plan_motion.h"
#include "plan_place.h"
#include "plan_problem.h"
#include "plan_search.h"
#include "racing.h"

namespace hfts::planner {

namespace {

/// What validating a successful plan checks, with the request's criteria
/// (defined with validatePlan).
ValidationRequest validationRequest(const PlanningWorld& world, const PlanRequest& request,
                                    const PlanResult& plan);
robot::Scene sceneOfPlan(const PlanningWorld& world, const PlanRequest& request,
                         const PlanResult& plan);

/// One search of the request over its shared problem (`problem`, with its
/// seed): from `result` (the request's fields filled) to the plan. The
/// planning time counts the teardown of everything this builds (trees,
/// caches, the sampling thread).
PlanResult search(std::chrono::steady_clock::time_point began, const SharedProblem& shared,
                  const PlanRequest& request, const std::optional<PlaceTarget>& place,
                  Problem& problem, const std::atomic<bool>* cancel, PlanResult result) {
  result.seed = problem.seed;
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
  result.clearance = found.path_check.clearance;
  result.grasp = describeGrasp(problem, found.goal);
  if (problem.lift) {
    // The baseline's goals were not checked for a lift: its first chance.
    std::string why;
    result.lift = found.lift ? std::move(found.lift)
                             : liftOf(problem, found.goal, result.stats,
                                      ob::plannerNonTerminatingCondition(), &why);
    if (!result.lift) {
      result.success = false;
      return failed(std::move(result), {PlanFailure::kLiftBlocked,
                                        "no lift of the grasp found is free (" + why + ")"});
    }
  }
  std::optional<Hold> hold;
  if (result.lift)
    hold =
        holdObject(shared.world.collisionModel(), shared.scene.robot_base, problem.object.geometry,
                   problem.object.name, shared.scene.target_pose, result.path.back());
  std::optional<PlaceOutcome> placed;
  if (place) {
    const auto placing = std::chrono::steady_clock::now();
    placed =
        planPlace(problem, *place, request.place_search, *hold, result.path[result.path.size() - 2],
                  result.path.back(), *result.lift, request.trajectory_rate, ptc);
    result.stats.place_time =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - placing).count();
    result.place_rejected = placed->rejected;
    result.stats.iterations += placed->iterations;
    result.stats.goal_sampling_calls += placed->goal_sampling_calls;
    result.stats.collision_checks += placed->collision_checks;
    result.stats.certificate_queries += placed->certificate_queries;
    if (!placed->placement) {
      result.success = false;
      return failed(std::move(result),
                    {cancel != nullptr && cancel->load() ? PlanFailure::kCancelled
                                                         : PlanFailure::kPlaceNotReached,
                     placed->why});
    }
    result.place = std::move(placed->placement);
  }
  if (found.verdict) {
    // The search simulated this grasp already: the same verdict.
    ValidationRequest v = validationRequest(shared.world, request, result);
    v.physics = false;
    result.validation = validateGrasp(shared.world, v);
    result.validation->physics = std::move(found.verdict);
  }
  if (request.trajectory_rate > 0.0 && shared.world.robot().maxAccelerations().size() > 0) {
    std::size_t queries = 0;
    const MotionCheck& check = problem.planner->smoothing().final_check;
    result.trajectory =
        graspTrajectory(result.path, problem.checker, check, request.trajectory_rate, &queries);
    if (result.lift) {
      const GraspTrajectory lift =
          liftTrajectory(*hold, shared.scene, *result.lift, check, request.trajectory_rate,
                         &queries, request.lift->held_speed);
      GraspTrajectory& t = result.trajectory;
      t.lift_start = appendTrajectory(t, lift);
      t.carry_start = t.place_start = t.release_start = t.retreat_start = t.duration;
      if (placed) {
        const double carry = appendTrajectory(t, placed->trajectory);
        t.carry_start = carry;
        t.place_start = carry + placed->descent_start;
        t.release_start = carry + placed->release_start;
        t.retreat_start = carry + placed->retreat_start;
        if (carry < 0.0) t.lift_start = -1.0;
      }
      // A part whose samples cannot be made free leaves no trajectory at all.
      if (t.lift_start < 0.0) result.trajectory = {};
    }
    result.stats.certificate_queries += queries;
  }
  return result;
}

/// planGrasp without the planning time: the request checked, its shared
/// problem set up once, then one search or `threads` racing ones over it.
PlanResult plan(std::chrono::steady_clock::time_point began, const PlanningWorld& world,
                const PlanRequest& request, const std::atomic<bool>* cancel) {
  quietOmpl();
  PlanResult result;
  result.seed = request.seed;
  result.joint_names = world.robot().dofNames();
  result.object_pose = request.object_pose.value_or(request.scene.target_pose);
  const Eigen::VectorXd start = startOf(world.robot(), request);
  checkLimits(request);
  const std::string name = objectNameOf(request);
  const db::ObjectDatabase* object = world.object(name);
  if (object == nullptr)
    return failed(std::move(result),
                  {PlanFailure::kUnknownObject, "unknown object '" + name + "'"});

  const SharedProblem shared(world, *object, request);
  result.object_pose = shared.scene.target_pose;
  // Where the object is to go, decided before any search.
  std::optional<PlaceTarget> place;
  if (request.place) {
    std::string why;
    std::tie(place, why) = placeTarget(shared.scene, *object, *request.place);
    if (!place) return failed(std::move(result), {PlanFailure::kNoStablePlacement, why});
  }
  // Why planning cannot start is asked once, on the first search's
  // problem (every copy would answer alike).
  Problem first(shared, request.seed, start);
  if (auto why = checkScene(first); why.first != PlanFailure::kNone)
    return failed(std::move(result), std::move(why));
  if (auto why = checkGraspable(first); why.first != PlanFailure::kNone)
    return failed(std::move(result), std::move(why));
  // The goal checks' model, compiled once before the searches (a
  // simulation's set-up cannot be stopped; its stop is polled only once it
  // runs).
  if (shared.settings.goal.physics_check && request.algorithm != PlanAlgorithm::kRrtConnect)
    physics::prepareSimulation(world.robot(), shared.scene, *object, shared.simulation);
  const int copies = shared.settings.execution.threads;
  if (copies == 1) return search(began, shared, request, place, first, cancel, result);
  return race(request.seed, cancel, copies,
              [&](int copy, std::uint64_t seed, const std::atomic<bool>* stop) {
                if (copy == 0) return search(began, shared, request, place, first, stop, result);
                Problem problem(shared, seed, start);
                return search(began, shared, request, place, problem, stop, result);
              });
}

}  // namespace

std::vector<PlannerParameterInfo> plannerParameters(const PlanningWorld& world) {
  return describeSettings(defaultSettings(world.robot()), world.robot());
}

PlanResult planGrasp(const PlanningWorld& world, const PlanRequest& request,
                     const std::atomic<bool>* cancel) {
  const auto began = std::chrono::steady_clock::now();
  if (request.goals.empty() && !world.canGrasp())
    throw InvalidArgument(
        "goals", "robot '" + world.robot().name() +
                     (world.robot().hasHand() ? "' has no hand map here (it holds an object)"
                                              : "' has no hand") +
                     ": it plans motions to goals only");
  if (request.validate && !request.goals.empty())
    throw InvalidArgument("validate", "a motion plan (goals) has no grasp to validate");
  if (request.validate) physics::validateOptions(request.simulation);
  if (request.lift) checkLiftOptions(*request.lift);
  if (request.place && !request.goals.empty())
    throw InvalidArgument("place", "a motion plan (goals) holds no object to place");
  if (request.place && !request.lift)
    throw InvalidArgument("place", "a pick and place lifts the object first: turn the lift on");
  PlanResult result = request.goals.empty() ? plan(began, world, request, cancel)
                                            : planMotion(began, world, request, cancel);
  result.stats.planning_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  if (request.validate && result.success && !result.validation)
    result.validation = validatePlan(world, request, result);
  else if (request.validate && result.success && result.place && !result.trajectory.points.empty())
    result.validation->place = simulatePlace(world, request, result);
  return result;
}

Validation validatePlan(const PlanningWorld& world, const PlanRequest& request,
                        const PlanResult& plan) {
  if (!plan.success || plan.path.size() < 2)
    throw InvalidArgument("plan", "only a successful plan has a grasp to validate");
  if (!request.goals.empty() || !world.robot().hasHand())
    throw InvalidArgument("plan", "a motion plan has no grasp to validate");
  Validation validation = validateGrasp(world, validationRequest(world, request, plan));
  if (plan.place && !plan.trajectory.points.empty())
    validation.place = simulatePlace(world, request, plan);
  return validation;
}

physics::PlaceVerdict simulatePlace(const PlanningWorld& world, const PlanRequest& request,
                                    const PlanResult& plan) {
  const robot::Scene scene = sceneOfPlan(world, request, plan);
  return physics::simulatePickAndPlace(
      world.collisionModel(), scene, *world.object(scene.target_object),
      plan.path[plan.path.size() - 2], plan.path.back(), placeMotion(plan), request.simulation);
}

physics::PlaceMotion placeMotion(const PlanResult& plan) {
  if (!plan.place || !plan.lift || plan.trajectory.points.empty())
    throw InvalidArgument("plan", "only a pick and place with a trajectory has a place motion");
  physics::PlaceMotion motion;
  motion.lift = plan.lift->path;
  const GraspTrajectory& t = plan.trajectory;
  for (const TrajectoryPoint& p : t.points) {
    if (p.time + 1e-9 < t.carry_start) continue;
    motion.times.push_back(p.time);
    motion.positions.push_back(p.positions);
  }
  motion.release_start = t.release_start;
  motion.place_pose = plan.place->object_pose;
  return motion;
}

namespace {

/// The scene the plan was made in: its object where the request puts it,
/// else where the plan had it, and sensed obstacles as the planner saw
/// them (SharedProblem::sceneOf).
robot::Scene sceneOfPlan(const PlanningWorld& world, const PlanRequest& request,
                         const PlanResult& plan) {
  PlanRequest made = request;
  if (!made.object_pose) made.object_pose = plan.object_pose;
  made.start = plan.path.front();
  const db::ObjectDatabase* object = world.object(objectNameOf(request));
  if (object == nullptr) throw InvalidArgument("plan", "its object is not in the world");
  return SharedProblem::sceneOf(made, *object, world.robot());
}

ValidationRequest validationRequest(const PlanningWorld& world, const PlanRequest& request,
                                    const PlanResult& plan) {
  ValidationRequest v;
  v.scene = sceneOfPlan(world, request, plan);
  v.pregrasp = plan.path[plan.path.size() - 2];
  v.grasp = plan.path.back();
  v.simulation = request.simulation;
  if (plan.lift) v.lift = plan.lift->path;
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
