#include "planner/grasp_motion_planner.h"

#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/util/Console.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <iomanip>
#include <limits>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>
#include <utility>
#include <vector>

#include "grasp/contact_mask.h"
#include "grasp/grasp_optimizer.h"
#include "grasp/grasp_quality.h"
#include "hfts_db/invalid_argument.h"
#include "planner/lazy_goal_baseline.h"
#include "planner/multi_tree_cbirrt.h"
#include "planner/sampling_tools.h"
#include "robot/kinematics.h"
#include "robot/object_surface.h"

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
    case PlanFailure::kNoValidGoal:
      return "no_valid_goal";
    case PlanFailure::kNoStableGraspClearOfSupport:
      return "no_stable_grasp_clear_of_support";
  }
  return "unknown";
}

namespace {

constexpr double kTreeResolution = 0.02;  // collision_resolution default (Eq. 3 metric)
/// Racing copies a request may ask for (parameter `threads`).
const ParameterRange kThreadsRange{1, 1, 32};

void quietOmpl() {
  static const bool once = [] {
    ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
    return true;
  }();
  (void)once;
}

/// Every parameter a request may set, in one set: the multi-tree planner's
/// own (its smoothing's included) and goal sampling's (the samplers' and
/// the objective's), merged. The RRTConnect baseline reads the same names.
struct PlanParameters {
  /// The defaults for `robot`: its fingertips' contact model, for two
  /// fingertips unstable pairs ranked by reach and Q = 0 for pairs the jaws
  /// cannot hold (grasp_objective.h), then
  /// its config's `planner_defaults` (robot::ModelError naming the one
  /// that is unknown or out of range).
  PlanParameters(const ob::SpaceInformationPtr& si, const robot::RobotModel& robot)
      : planner(std::make_shared<MultiTreeCBiRRT>(si)) {
    all.include(planner->params());
    declareParameters(all, goals);
    declareParameter(all, "sphere_tier", {0, 1, 1}, sphereTier);
    declareParameter(all, "threads", kThreadsRange, threads);  // planGrasp reads it
    declareParameter(all, "physics_check", {0, 1, 1}, physicsCheck);
    goals.objective.torsional_friction = robot.torsionalFriction();
    goals.objective.unstable_by_reach = robot.fingertips().size() == 2 ? 1 : 0;
    goals.objective.fit_check = robot.fingertips().size() == 2 ? 1 : 0;
    for (const auto& [name, value] : robot.plannerDefaults()) {
      try {
        setParameter(all, name, value);
      } catch (const InvalidArgument& e) {
        throw robot::ModelError("robot config '" + robot.name() + "': planner_defaults." + name +
                                ": " + e.problem());
      }
    }
  }
  /// The request's parameters over the robot's defaults.
  PlanParameters(const ob::SpaceInformationPtr& si, const PlanRequest& request,
                 const robot::RobotModel& robot)
      : PlanParameters(si, robot) {
    set(request);
  }
  PlanParameters(const PlanParameters&) = delete;
  PlanParameters& operator=(const PlanParameters&) = delete;

  /// The request's parameters, then its top-level `iterations`.
  void set(const PlanRequest& request) {
    for (const auto& [name, value] : request.parameters) setParameter(all, name, value);
    if (!request.iterations) return;
    try {
      setParameter(all, "iterations", std::to_string(*request.iterations));
    } catch (const InvalidArgument& e) {
      throw InvalidArgument("iterations", e.problem());
    }
  }

  std::shared_ptr<MultiTreeCBiRRT> planner;
  GoalSamplingSettings goals;
  /// 1: collision checks in two tiers (spheres, then FCL on the touching
  /// pairs); 0: FCL alone. The same answers either way (docs/collision.md).
  int sphereTier = 1;
  /// Racing copies of the search (planGrasp); each copy is one thread.
  int threads = 1;
  /// 1: a goal the trees reach ends the search only when its grasp holds
  /// in physics (physics::simulateGrasp with the request's simulation
  /// options); else its tree is dropped and the search goes on. 0: every
  /// reached goal ends it (the paper's Algorithm 1).
  int physicsCheck = 1;
  ob::ParamSet all;
};

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

/// One plan's problem, set up in order: the scene as requested, its
/// collision checker and OMPL space information, the parameters, the
/// object's HFTS.
struct Problem {
  Problem(const PlanningWorld& w, const db::ObjectDatabase& o, const PlanRequest& request,
          Eigen::VectorXd q0)
      : world(w),
        object(o),
        scene(sceneOf(request, o)),
        start(std::move(q0)),
        seed(request.seed),
        explored(request.explored),
        simulation(request.simulation),
        checker(w.robot(), scene, &o.geometry, w.collisionMesh(o.name), w.surface(o.name)),
        si(makeSpaceInformation(w.robot(), checker, kTreeResolution)),
        parameters(si, request, w.robot()),
        // A robot whose fingertips have no measurable pad is not masked.
        usable(
            parameters.goals.mask_contacts == 0 || w.padRadius() <= grasp::kContactMaskClearance
                ? std::vector<bool>{}
                : grasp::fingertipReachableContacts(o, scene.target_pose, checker, w.padRadius())),
        space(o, static_cast<int>(w.robot().fingertips().size()),
              usable.empty() ? nullptr : &usable) {
    checker.setSphereTier(parameters.sphereTier != 0);
    checker.setMaxPenetration(parameters.goals.max_penetration);
  }

  /// The request's object where the request puts it: at object_pose, or
  /// at the scene's target pose (resting on its support when it has one).
  static robot::Scene sceneOf(const PlanRequest& request, const db::ObjectDatabase& object) {
    robot::Scene s = request.scene;
    s.target_object = object.name;
    s.target_pose = request.object_pose
                        ? *request.object_pose
                        : robot::targetPose(request.scene, object.geometry.mesh_vertices);
    s.target_rest_on.clear();  // placed
    return s;
  }

  const PlanningWorld& world;
  const db::ObjectDatabase& object;
  const robot::Scene scene;
  const Eigen::VectorXd start;
  const std::uint64_t seed;
  const bool explored;                          ///< record the goal hierarchy cache's nodes
  const physics::SimulationOptions simulation;  ///< of physics_check and validate
  robot::CollisionChecker checker;
  const ob::SpaceInformationPtr si;
  PlanParameters parameters;
  /// Contacts a fingertip can touch here (empty: mask_contacts off, all).
  const std::vector<bool> usable;
  const grasp::HftsSpace space;
};

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

/// What a search found (a path from the start to a goal's pre-grasp) and
/// how it went.
struct SearchOutcome {
  bool solved = false;
  std::vector<ExploredNode> explored;
  std::vector<Eigen::VectorXd> path;
  GoalSample goal;
  GoalSamplerStatistics goals;
  PlanStatistics stats;
  /// With physics_check: the verdict of the goal the search ended at.
  std::optional<physics::GraspVerdict> verdict;
};

/// The goal check of physics_check: the reached goal's grasp simulated
/// (its verdict kept for the result). A grasp that failed is not simulated
/// again for another arm configuration with the same closed hand.
MultiTreeCBiRRT::GoalCheck physicsGoalCheck(const Problem& p, SearchOutcome& out,
                                            const ob::PlannerTerminationCondition& ptc) {
  auto failed = std::make_shared<std::set<const grasp::HandClosure*>>();
  return [&p, &out, &ptc, failed](const GoalSample& goal) {
    if (failed->count(goal.closure.get()) > 0) return false;
    // Within the time limit: a plan whose grasp could not be checked in
    // time is no plan.
    physics::SimulationOptions options = p.simulation;
    options.stop_when_lost = true;
    options.stop = [&ptc] { return ptc(); };
    physics::GraspVerdict verdict = physics::simulateGrasp(p.world.robot(), p.scene, p.object,
                                                           goal.configuration, goal.grasp, options);
    if (!verdict.held) {
      failed->insert(goal.closure.get());
      return false;
    }
    out.verdict = std::move(verdict);
    return true;
  };
}

std::vector<ExploredNode> exploredNodes(const GoalHierarchyCache& cache, SamplingTools& tools) {
  std::vector<ExploredNode> out;
  for (std::size_t n = 1; n < cache.size(); ++n) {
    const CacheNode& node = cache.node(static_cast<int>(n));
    const grasp::GraspEvaluation e = tools.objective.evaluate(node.hfts);
    ExploredNode x;
    x.level = node.hfts.level;
    x.contacts_object = tools.space.representative(node.hfts).positions;
    x.value = e.value;
    x.quality = e.quality;
    x.goal = std::any_of(node.configurations.begin(), node.configurations.end(),
                         [](const CachedConfiguration& c) { return c.goal; });
    out.push_back(std::move(x));
  }
  return out;
}

/// The multi-tree CBiRRT (Algorithm 1) with the coupled goal sampler
/// (Algorithm 2) or the decoupled one.
SearchOutcome searchMultiTree(Problem& p, bool coupled,
                              const ob::PlannerTerminationCondition& ptc) {
  MultiTreeCBiRRT& planner = *p.parameters.planner;
  SamplingTools tools(p.world, p.scene, p.space, p.checker, p.parameters.goals);
  tools.configurator.setArmReference(p.start.head(p.world.robot().numArmDofs()));
  const std::unique_ptr<GraspGoalSampler> sampler = tools.makeSampler(
      coupled, planner.rng(), p.parameters.goals, planner.smoothing().final_resolution);
  planner.setProjection(std::make_shared<BackwardProjection>(
      p.world.robot(), p.scene.robot_base, p.scene.target_pose * p.object.geometry.center_of_mass,
      planner.getProjectionDistance()));
  auto pdef = std::make_shared<ob::ProblemDefinition>(p.si);
  ob::ScopedState<> startState(p.si);
  weightedSpace(p.si).fromVector(p.start, startState.get());
  pdef->addStartState(startState);
  pdef->setGoal(std::make_shared<GraspGoal>(p.si, *sampler));
  planner.setProblemDefinition(pdef);
  planner.setSeed(p.seed);
  planner.setup();

  SearchOutcome out;
  // The goal checks' model, compiled before the search (a simulation's
  // set-up cannot be stopped; its stop is polled only once it runs).
  if (p.parameters.physicsCheck != 0)
    physics::prepareSimulation(p.world.robot(), p.scene, p.object, p.simulation);
  planner.setGoalCheck(p.parameters.physicsCheck != 0 ? physicsGoalCheck(p, out, ptc)
                                                      : MultiTreeCBiRRT::GoalCheck{});
  out.solved = planner.solve(ptc) == ob::PlannerStatus::EXACT_SOLUTION;
  out.goals = sampler->statistics();
  out.stats = planStatistics(planner.statistics(), out.goals, tools.objective.evaluations(),
                             p.checker.checkCount());
  if (const auto* hfts = dynamic_cast<const HftsGoalSampler*>(sampler.get());
      hfts != nullptr && p.explored)
    out.explored = exploredNodes(hfts->cache(), tools);
  if (out.solved) {
    out.path = planner.solutionPath();
    out.goal = planner.reachedGoal();
  }
  return out;
}

/// The outside baseline: OMPL's RRTConnect towards lazily sampled
/// decoupled goals.
SearchOutcome searchBaseline(Problem& p, const ob::PlannerTerminationCondition& ptc) {
  LazyGoalRrtConnect baseline(p.si, p.world, p.scene, p.object, p.space,
                              {p.parameters.goals, p.parameters.planner->smoothing(), p.seed});
  LazyGoalOutcome found = baseline.solve(p.start, ptc);
  SearchOutcome out;
  out.solved = found.solved;
  out.path = std::move(found.path);
  out.goal = std::move(found.goal);
  out.goals = found.goals;
  out.stats = planStatistics(found.trees, found.goals, found.objective_evaluations,
                             p.checker.checkCount() + found.sampling_collision_checks);
  return out;
}

/// "a unstable, b without arm IK, ..." for the reasons that occurred.
std::string rejectionText(const GraspRejections& r) {
  std::string out;
  for (const auto& [count, what] :
       {std::pair{r.unstable, "unstable (no force closure)"},
        std::pair{r.no_arm_ik, "without arm IK solution"},
        std::pair{r.out_of_hand_reach, "out of the hand's reach"},
        std::pair{r.colliding, "colliding"},
        std::pair{r.no_pad_contact, "without every pad on the object when the hand closes"},
        std::pair{r.weak_at_contacts, "below min_epsilon where the pads touch"},
        std::pair{r.closing_blocked, "closing blocked"}})
    if (count > 0) out += (out.empty() ? "" : ", ") + std::to_string(count) + " " + what;
  return out.empty() ? "none tried" : out;
}

/// Why a search found nothing.
std::pair<PlanFailure, std::string> failureOf(const SearchOutcome& found,
                                              const std::atomic<bool>* cancel) {
  const GoalSamplerStatistics& goals = found.goals;
  if (cancel != nullptr && cancel->load()) return {PlanFailure::kCancelled, "cancelled"};
  if (goals.configured_nodes > 0 && goals.kinematic_solutions == 0)
    return {PlanFailure::kObjectUnreachable,
            "none of the " + std::to_string(goals.configured_nodes) +
                " grasps tried has an arm IK solution: the object is out of reach"};
  if (goals.valid_goals == 0)
    return {PlanFailure::kNoValidGoal, "no valid goal within the time limit; of the " +
                                           std::to_string(goals.rejected.total()) +
                                           " leaf grasps tried: " + rejectionText(goals.rejected)};
  std::string dropped;
  if (found.stats.dropped_goals > 0)
    dropped = " (the paths to " + std::to_string(found.stats.dropped_goals) +
              " of them ended in grasps that did not hold in physics)";
  return {PlanFailure::kTimeLimit, "no path to any of the " + std::to_string(goals.valid_goals) +
                                       " goals found within the time limit" + dropped};
}

/// How deep the robot's fingertip links at q reach into the target (m, >= 0).
double fingertipPenetration(const Problem& p, const Eigen::VectorXd& q) {
  const robot::RobotModel& robot = p.world.robot();
  const robot::ObjectSurface* surface = p.world.surface(p.object.name);
  if (surface == nullptr) return 0.0;
  const robot::LinkPoses poses = robot::forwardKinematics(robot, q);
  const Eigen::Isometry3d baseInObject = p.scene.target_pose.inverse() * p.scene.robot_base;
  double depth = 0.0;
  for (const robot::Fingertip& tip : robot.fingertips()) {
    constexpr double kTolerance = 5e-5;
    const auto link = static_cast<std::size_t>(tip.link);
    depth = std::max(
        depth, surface->linkDepth(robot.links()[link], baseInObject * poses[link], kTolerance));
  }
  return depth;
}

PlannedGrasp describeGrasp(const Problem& p, const GoalSample& goal) {
  const robot::RobotModel& robot = p.world.robot();
  const Eigen::Isometry3d& objectPose = p.scene.target_pose;
  const grasp::GraspContacts touched = goal.closure->contacts();
  PlannedGrasp g;
  g.node = goal.node;
  g.contacts_object = touched.positions;
  g.contacts_world = objectPose * touched.positions;
  g.inward_normals_object = -touched.outward_normals;
  g.inward_normals_world = objectPose.linear() * g.inward_normals_object;
  g.epsilon = goal.contact_epsilon;
  g.planned_contacts_object = goal.contacts.positions;
  g.planned_epsilon = goal.epsilon;
  g.reachability = goal.reachability;
  g.fingertip_error = goal.fingertip_error;
  g.penetration = fingertipPenetration(p, goal.grasp);
  g.hand_configuration = goal.grasp.tail(robot.numHandDofs());
  return g;
}

/// What validating a successful plan checks, with the request's criteria
/// (defined with validatePlan).
ValidationRequest validationRequest(const PlanningWorld& world, const PlanRequest& request,
                                    const PlanResult& plan);

PlanResult failed(PlanResult result, std::pair<PlanFailure, std::string> why) {
  result.failure = why.first;
  result.message = std::move(why.second);
  return result;
}

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
    result.trajectory = graspTrajectory(result.path, problem.checker,
                                        problem.parameters.planner->smoothing().final_resolution,
                                        request.trajectory_rate);
  return result;
}

/// The request's `threads` parameter, checked as the full set checks it.
int threadsOf(const PlanRequest& request) {
  const auto it = request.parameters.find("threads");
  if (it == request.parameters.end()) return 1;
  ob::ParamSet only;
  int threads = 1;
  declareParameter(only, "threads", kThreadsRange, threads);
  setParameter(only, "threads", it->second);
  return threads;
}

/// `copies` searches race (planGrasp): copy i plans with racingSeed(seed,
/// i) in its own thread; the first plan stops the others. `cancel` stops
/// all of them.
PlanResult race(std::chrono::steady_clock::time_point began, const PlanningWorld& world,
                const PlanRequest& request, const std::atomic<bool>* cancel, int copies) {
  const auto n = static_cast<std::size_t>(copies);
  std::atomic<bool> stop{false};
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<PlanResult> results(n);
  std::vector<std::exception_ptr> errors(n);
  std::size_t finished = 0;
  std::optional<std::size_t> winner;
  std::vector<std::thread> threads;
  threads.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
    threads.emplace_back([&, i] {
      PlanRequest copy = request;
      copy.seed = racingSeed(request.seed, static_cast<int>(i));
      PlanResult found;
      std::exception_ptr error;
      try {
        found = planFrom(began, world, copy, &stop);
      } catch (...) {
        error = std::current_exception();
      }
      const std::lock_guard<std::mutex> lock(mutex);
      if (found.success && !winner) winner = i;
      if (winner || error) stop = true;
      results[i] = std::move(found);
      errors[i] = error;
      ++finished;
      changed.notify_all();
    });
  {
    std::unique_lock<std::mutex> lock(mutex);
    while (finished < n)
      if (!changed.wait_for(lock, std::chrono::milliseconds(5), [&] { return finished == n; }) &&
          cancel != nullptr && cancel->load())
        stop = true;
  }
  for (std::thread& t : threads) t.join();
  for (const std::exception_ptr& error : errors)
    if (error) std::rethrow_exception(error);  // every copy checks the same request
  PlanResult result = std::move(results[winner.value_or(0)]);
  if (!winner && cancel != nullptr && cancel->load())
    return failed(std::move(result), {PlanFailure::kCancelled, "cancelled"});
  return result;
}

}  // namespace

std::uint64_t racingSeed(std::uint64_t seed, int copy) {
  if (copy == 0) return seed;
  std::uint64_t z = seed + 0x9e3779b97f4a7c15ULL * static_cast<std::uint64_t>(copy);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

std::vector<PlannerParameterInfo> plannerParameters(const PlanningWorld& world) {
  quietOmpl();
  robot::CollisionChecker checker(world.robot(), robot::Scene{}, nullptr);
  const PlanParameters parameters(makeSpaceInformation(world.robot(), checker, kTreeResolution),
                                  world.robot());
  std::vector<PlannerParameterInfo> out;
  for (const auto& [name, param] : parameters.all.getParams())
    out.push_back({name, param->getValue(), param->getRangeSuggestion()});
  return out;
}

PlanResult planGrasp(const PlanningWorld& world, const PlanRequest& request,
                     const std::atomic<bool>* cancel) {
  const auto began = std::chrono::steady_clock::now();
  if (request.validate) physics::validateOptions(request.simulation);
  const int copies = threadsOf(request);
  PlanResult result = copies == 1 ? planFrom(began, world, request, cancel)
                                  : race(began, world, request, cancel, copies);
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
  robot::CollisionChecker checker(world.robot(), robot::Scene{}, nullptr);
  const PlanParameters parameters(makeSpaceInformation(world.robot(), checker, kTreeResolution),
                                  request, world.robot());
  v.check.min_epsilon = parameters.goals.min_epsilon;
  v.check.max_penetration = parameters.goals.max_penetration;
  v.check.resolution = parameters.planner->smoothing().final_resolution;
  v.check.friction = parameters.goals.objective.friction;
  return v;
}

}  // namespace

namespace {

/// The hand alone at `palm` (world frame): pre-grasp, closing motion and
/// grasp clear (holdability's criterion).
bool handFits(robot::CollisionChecker& checker, const Eigen::Isometry3d& palm,
              const Eigen::VectorXd& pregrasp, const Eigen::VectorXd& grasp) {
  if (checker.handInCollision(palm, pregrasp, false)) return false;
  // The closing motion, its last state the grasp.
  constexpr int kClosingSteps = 8;
  for (int k = 1; k <= kClosingSteps; ++k) {
    const double t = static_cast<double>(k) / kClosingSteps;
    if (checker.handInCollision(palm, pregrasp + t * (grasp - pregrasp), true)) return false;
  }
  return true;
}

}  // namespace

Holdability holdability(const PlanningWorld& world, const PlanRequest& request, int climbs) {
  if (climbs < 1) throw InvalidArgument("climbs", "must be at least 1");
  quietOmpl();
  Holdability out;
  const std::string name = objectNameOf(request);
  const db::ObjectDatabase* object = world.object(name);
  if (object == nullptr) {
    out.reason = "unknown object '" + name + "'";
    return out;
  }
  Problem p(world, *object, request, startOf(world.robot(), request));
  auto cannot = checkTarget(p);
  if (cannot.first == PlanFailure::kNone) cannot = checkGraspable(p);
  if (cannot.first != PlanFailure::kNone) {
    out.reason = cannot.second;
    return out;
  }
  // The question is whether any grasp exists: the objective ranks grasps
  // whose hand meets an obstacle last (hand_clearance).
  GoalSamplingSettings settings = p.parameters.goals;
  settings.hand_clearance = 1;
  SamplingTools tools(world, p.scene, p.space, p.checker, settings);
  tools.configurator.setArmReference(p.start.head(world.robot().numArmDofs()));
  std::mt19937_64 rng(request.seed);
  // The hand alone closed from the pre-grasp until its pads touch.
  const auto fits = [&](const grasp::HandQuery& hand) {
    if (!tools.closer) return false;
    const Eigen::VectorXd pregrasp = tools.configurator.openedHand(hand.hand_configuration);
    const int turns = hand.free_turn ? settings.palm_turns : 1;
    for (int k = 0; k < turns; ++k) {
      const Eigen::Isometry3d palm = grasp::turnedPalm(hand, 2.0 * M_PI * k / turns);
      // The cheap check first: closing costs milliseconds.
      if (p.checker.handInCollision(p.scene.target_pose * palm, pregrasp, false)) continue;
      const grasp::HandClosure closed =
          tools.closer->close(palm, pregrasp, hand.hand_configuration);
      if (closed.touches() &&
          handFits(p.checker, p.scene.target_pose * closed.palm, pregrasp, closed.hand))
        return true;
    }
    return false;
  };
  // A collision-free robot configuration with the fingertips on the
  // contacts, for a hand posture whose hand alone fits (Phi(h)).
  const auto robotHolds = [&](const grasp::GraspContacts& contacts, const grasp::HandQuery& hand) {
    const grasp::GraspConfigurations all =
        tools.configurator.configure(contacts, hand, rng, true, /*close=*/true);
    return std::any_of(
        all.configurations.begin(), all.configurations.end(),
        [&](const grasp::GraspConfiguration& c) {
          return c.label == grasp::ConfigurationLabel::kCollisionFree &&
                 c.fingertip_error <= settings.max_fingertip_error && c.closure &&
                 c.closure->touches() &&
                 grasp::graspQuality(
                     grasp::qualityRequest(p.space, c.closure->contacts(), settings.objective))
                         .epsilon >= std::max(settings.min_epsilon, 1e-300);
        });
  };
  // Whether the robot takes the leaf's contacts: R(h)'s posture, then the
  // hand's other ways of taking them (the planner's other_postures).
  const auto held = [&](const grasp::HftsNode& leaf, bool& reached, bool& handClear) {
    const grasp::GraspContacts contacts = p.space.representative(leaf);
    const grasp::HandQuery first =
        world.thoroughHandMap().query(contacts.positions, contacts.outward_normals);
    reached = first.position_error <= settings.max_fingertip_error;
    if (reached && fits(first)) {
      handClear = true;
      if (robotHolds(contacts, first)) return true;
    }
    for (const grasp::HandQuery& hand : world.thoroughHandMap().queryAlternatives(
             contacts.positions, contacts.outward_normals, settings.max_fingertip_error)) {
      reached = true;
      if (!fits(hand)) continue;
      handClear = true;
      if (robotHolds(contacts, hand)) return true;
    }
    return false;
  };
  // Each climb ends one level above the leaves, at a node not climbed to
  // before; all of its leaves are then tried.
  const int last = p.space.numLevels() - 1;
  std::vector<std::unordered_set<grasp::HftsNode, grasp::HftsNodeHash>> excluded(
      static_cast<std::size_t>(last) + 1);
  while (out.climbs < climbs) {
    // Every other descent is a random walk: Eq. (1) prefers the best
    // grasps, and a hand may hold an object only by weaker ones.
    const bool climbing = out.climbs % 2 == 0;
    grasp::HftsNode node = p.space.root();
    while (node.level < last) {
      const auto& skip = excluded[static_cast<std::size_t>(node.level) + 1];
      if (climbing) {
        const grasp::ClimbResult climb =
            grasp::hillClimb(tools.objective, node, settings.decoupled_iterations, rng, &skip);
        if (!climb.found) break;
        node = climb.best;
      } else {
        const std::uint64_t n = p.space.numChildren(node);
        if (n == 0) break;
        const std::uint64_t start = std::uniform_int_distribution<std::uint64_t>(0, n - 1)(rng);
        std::uint64_t k = 0;
        while (k < n && skip.count(p.space.child(node, (start + k) % n)) > 0) ++k;
        if (k == n) break;
        node = p.space.child(node, (start + k) % n);
      }
      // Spread out: no two descents pass through the same node.
      excluded[static_cast<std::size_t>(node.level)].insert(node);
    }
    if (node.level < last) {  // all below it tried
      if (node.level == 0) break;
      excluded[static_cast<std::size_t>(node.level)].insert(node);
      continue;
    }
    if (last == 0 && out.climbs > 0) break;  // one level: the root's leaves were all tried
    excluded[static_cast<std::size_t>(last)].insert(node);
    ++out.climbs;
    for (std::uint64_t c = 0; c < p.space.numChildren(node); ++c) {
      const grasp::HftsNode leaf = p.space.child(node, c);
      ++out.leaves;
      const double quality = tools.objective.evaluate(leaf).quality;
      if (!(quality > 0.0)) continue;
      ++out.stable;
      bool reached = false, handClear = false;
      const bool holds = held(leaf, reached, handClear);
      if (reached) ++out.reached;
      if (handClear) ++out.hand_clear;
      if (holds) {
        out.holdable = true;
        out.epsilon = quality;
        return out;
      }
    }
  }
  std::ostringstream why;
  why << "no grasp in " << out.leaves << " leaves of " << out.climbs << " climbs: " << out.stable
      << " stable, " << out.reached << " of them within the fingertips' reach, " << out.hand_clear
      << " of those with the hand alone clear of the scene, none with a "
      << "collision-free arm configuration";
  out.reason = why.str();
  return out;
}

}  // namespace hfts::planner
