#include "planner/grasp_motion_planner.h"

#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/util/Console.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "planner/lazy_goal_baseline.h"
#include "planner/multi_tree_cbirrt.h"

namespace hfts::planner {

namespace ob = ompl::base;

const char* toString(PlanFailure failure) {
  switch (failure) {
    case PlanFailure::kNone:
      return "none";
    case PlanFailure::kTimeLimit:
      return "time_limit";
    case PlanFailure::kCancelled:
      return "cancelled";
    case PlanFailure::kStartInCollision:
      return "start_in_collision";
    case PlanFailure::kObjectInCollision:
      return "object_in_collision";
    case PlanFailure::kObjectUnreachable:
      return "object_unreachable";
    case PlanFailure::kUnknownObject:
      return "unknown_object";
  }
  return "unknown";
}

namespace {

constexpr double kTreeResolution = 0.02;  // collision_resolution default (Eq. 3 metric)

void quietOmpl() {
  static const bool once = [] {
    ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
    return true;
  }();
  (void)once;
}

std::shared_ptr<MultiTreeCBiRRT> makePlanner(const ob::SpaceInformationPtr& si,
                                             const PlanRequest& request) {
  auto planner = std::make_shared<MultiTreeCBiRRT>(si);
  if (request.time_limit) planner->setTimeLimit(*request.time_limit);
  std::map<std::string, std::string> parameters = request.parameters;
  if (request.iterations) parameters["iterations"] = std::to_string(*request.iterations);
  for (const auto& [name, value] : parameters) {
    if (!planner->params().hasParam(name))
      throw std::invalid_argument("parameters: unknown planner parameter '" + name + "'");
    if (!planner->params().setParam(name, value))
      throw std::invalid_argument("parameters: '" + value + "' is not a valid value for '" + name +
                                  "' (range " + planner->params()[name].getRangeSuggestion() + ")");
  }
  return planner;
}

Eigen::VectorXd startOf(const robot::RobotModel& robot, const PlanRequest& request) {
  const Eigen::VectorXd start =
      request.start ? *request.start : request.scene.start.value_or(robot.home());
  if (start.size() != robot.numDofs())
    throw std::invalid_argument("start: " + std::to_string(robot.numDofs()) +
                                " values expected, got " + std::to_string(start.size()));
  if (!start.allFinite()) throw std::invalid_argument("start: values must be finite");
  std::string which;
  if (!robot.withinLimits(start, 1e-9, &which)) throw std::invalid_argument("start: " + which);
  return start;
}

PlannedGrasp describeGrasp(const robot::RobotModel& robot, const GoalSample& goal,
                           const Eigen::Isometry3d& objectPose) {
  PlannedGrasp g;
  g.node = goal.node;
  g.contacts_object = goal.contacts.positions;
  g.contacts_world = objectPose * goal.contacts.positions;
  g.inward_normals_object = -goal.contacts.outward_normals;
  g.inward_normals_world = objectPose.linear() * g.inward_normals_object;
  g.epsilon = goal.epsilon;
  g.reachability = goal.reachability;
  g.fingertip_error = goal.fingertip_error;
  g.hand_configuration = goal.grasp.tail(robot.numHandDofs());
  return g;
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

/// The baseline reads the multi-tree planner's parameters of the same meaning.
LazyGoalSettings lazyGoalSettings(const MultiTreeCBiRRT& planner, std::uint64_t seed) {
  const GoalSamplingParameters& g = planner.goalSampling();
  LazyGoalSettings s;
  s.iterations = g.decoupled_iterations;
  s.objective = {g.alpha, g.friction, g.cone_edges};
  s.max_fingertip_error = g.max_fingertip_error;
  s.smoothing.steps = planner.getSmoothingSteps();
  s.smoothing.final_resolution = planner.getFinalCheckResolution();
  s.seed = seed;
  return s;
}

void recordBaseline(const LazyGoalOutcome& out, std::uint64_t plannerChecks, PlanStatistics& s) {
  s.iterations = out.iterations;
  s.goal_sampling_calls = out.goals.calls;
  s.valid_goal_samples = out.goals.valid_goals;
  s.hfts_nodes_explored = out.goals.nodes_explored;
  s.objective_evaluations = out.objective_evaluations;
  s.goal_trees = out.goal_states_taken;
  s.collision_checks = plannerChecks + out.sampling_collision_checks;
  s.forward_tree_size = out.start_tree_size;
  s.backward_tree_nodes = out.goal_tree_size;
  s.path_length_raw = out.path_length_raw;
  s.path_length_smoothed = out.path_length_smoothed;
}

}  // namespace

std::vector<PlannerParameterInfo> plannerParameters(const PlanningWorld& world) {
  quietOmpl();
  robot::CollisionChecker checker(world.robot(), robot::Scene{}, nullptr);
  const auto si = makeSpaceInformation(world.robot(), checker, kTreeResolution);
  MultiTreeCBiRRT planner(si);
  std::vector<PlannerParameterInfo> out;
  for (const auto& [name, param] : planner.params().getParams())
    out.push_back({name, param->getValue(), param->getRangeSuggestion()});
  return out;
}

namespace {

/// planGrasp without the planning time, which counts the teardown of
/// everything this builds (trees, caches, checkers, the sampling thread).
PlanResult planFrom(std::chrono::steady_clock::time_point began, const PlanningWorld& world,
                    const PlanRequest& request, const std::atomic<bool>* cancel) {
  quietOmpl();
  const robot::RobotModel& robot = world.robot();
  PlanResult result;
  result.joint_names = robot.dofNames();
  const std::string name = request.object.empty() ? request.scene.target_object : request.object;
  const Eigen::VectorXd start = startOf(robot, request);
  if (request.time_limit && !(*request.time_limit >= 0.0))
    throw std::invalid_argument("time_limit must be a number >= 0");
  const db::ObjectDatabase* object = world.object(name);
  auto finish = [&](PlanFailure failure, std::string message) {
    result.failure = failure;
    result.message = std::move(message);
    return result;
  };
  if (object == nullptr)
    return finish(PlanFailure::kUnknownObject, "unknown object '" + name + "'");

  robot::Scene scene = request.scene;
  scene.target_object = name;
  if (request.object_pose) scene.target_pose = *request.object_pose;
  robot::CollisionChecker checker(robot, scene, &object->geometry, world.collisionMesh(name));
  const auto si = makeSpaceInformation(robot, checker, kTreeResolution);
  const std::shared_ptr<MultiTreeCBiRRT> planner = makePlanner(si, request);
  robot::CollisionPair pair;
  if (checker.targetTouchesObstacles(&pair))
    return finish(PlanFailure::kObjectInCollision,
                  "the target object intersects " + pair.second + " in this scene");
  if (checker.inCollision(start, &pair))
    return finish(PlanFailure::kStartInCollision, "the start configuration is in collision: " +
                                                      pair.first + " touches " + pair.second);

  const GoalSamplingParameters& g = planner->goalSampling();
  const grasp::HftsSpace space(*object, static_cast<int>(robot.fingertips().size()));
  auto succeed = [&](std::vector<Eigen::VectorXd> path, const GoalSample& goal) {
    result.success = true;
    result.path = std::move(path);
    result.path.push_back(goal.grasp);
    result.grasp = describeGrasp(robot, goal, scene.target_pose);
    return finish(PlanFailure::kNone, "");
  };
  auto fail = [&](const GoalSamplerStatistics& goals) {
    if (cancel != nullptr && cancel->load()) return finish(PlanFailure::kCancelled, "cancelled");
    if (goals.configured_nodes > 0 && goals.kinematic_solutions == 0)
      return finish(PlanFailure::kObjectUnreachable,
                    "none of the " + std::to_string(goals.configured_nodes) +
                        " grasps tried has an arm IK solution: the object is out of reach");
    return finish(PlanFailure::kTimeLimit, "no grasp reached within the time limit");
  };
  if (request.algorithm == PlanAlgorithm::kRrtConnect) {
    LazyGoalRrtConnect baseline(si, world, scene, *object, space,
                                lazyGoalSettings(*planner, request.seed));
    const LazyGoalOutcome out =
        baseline.solve(start, terminationCondition(planner->getTimeLimit(), began, cancel));
    recordBaseline(out, checker.checkCount(), result.stats);
    return out.solved ? succeed(out.path, out.goal) : fail(out.goals);
  }
  grasp::GraspObjective objective(space, world.handMap(), {g.alpha, g.friction, g.cone_edges});
  grasp::GraspConfigurator configurator(robot, world.ik(), world.thoroughHandMap(), checker,
                                        scene.target_pose, scene.robot_base);
  GoalSamplingContext context{&space,
                              &objective,
                              &configurator,
                              &checker,
                              &planner->rng(),
                              planner->getFinalCheckResolution(),
                              g.max_fingertip_error};
  std::unique_ptr<GoalSampler> sampler;
  if (request.algorithm == PlanAlgorithm::kCoupled)
    sampler = std::make_unique<HftsGoalSampler>(
        context, HftsGoalSamplerOptions{g.weights, g.kappa, g.i_min, g.i_max});
  else
    sampler = std::make_unique<DecoupledGoalSampler>(context, g.decoupled_iterations);
  planner->setProjection(std::make_shared<BackwardProjection>(
      robot, scene.robot_base, scene.target_pose * object->geometry.center_of_mass,
      planner->getProjectionDistance()));

  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<> startState(si);
  si->getStateSpace()->as<WeightedStateSpace>()->fromVector(start, startState.get());
  pdef->addStartState(startState);
  pdef->setGoal(std::make_shared<GraspGoal>(si, *sampler));
  planner->setProblemDefinition(pdef);
  planner->setSeed(request.seed);
  planner->setup();

  const ob::PlannerStatus status =
      planner->solve(terminationCondition(planner->getTimeLimit(), began, cancel));

  const TreeStatistics& trees = planner->statistics();
  const GoalSamplerStatistics& goals = sampler->statistics();
  PlanStatistics& s = result.stats;
  s.iterations = trees.iterations;
  s.goal_sampling_calls = goals.calls;
  s.valid_goal_samples = goals.valid_goals;
  s.hfts_nodes_explored = goals.nodes_explored;
  s.objective_evaluations = objective.evaluations();
  s.goal_trees = trees.goal_trees;
  s.approximate_trees = trees.approximate_trees;
  s.merged_trees = trees.merged_trees;
  s.rejected_paths = trees.rejected_paths;
  s.collision_checks = checker.checkCount();
  s.forward_tree_size = trees.forward_tree_size;
  s.backward_tree_nodes = trees.backward_tree_nodes;
  s.path_length_raw = trees.path_length_raw;
  s.path_length_smoothed = trees.path_length_smoothed;

  if (status == ob::PlannerStatus::EXACT_SOLUTION)
    return succeed(planner->solutionPath(), planner->reachedGoal());
  return fail(goals);
}

}  // namespace

PlanResult planGrasp(const PlanningWorld& world, const PlanRequest& request,
                     const std::atomic<bool>* cancel) {
  const auto began = std::chrono::steady_clock::now();
  PlanResult result = planFrom(began, world, request, cancel);
  result.stats.planning_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  return result;
}

}  // namespace hfts::planner
