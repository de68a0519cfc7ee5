#include "planner/lazy_goal_baseline.h"

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/goals/GoalLazySamples.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>

#include <chrono>
#include <exception>
#include <limits>
#include <mutex>
#include <random>
#include <stdexcept>
#include <thread>
#include <utility>

#include "core/invalid_argument.h"
#include "planner/configuration_space.h"
#include "planner/sampling_tools.h"

namespace hfts::planner {

namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace {

/// The decoupled optimiser ignores what the motion planner knows.
class NoFreeSpaceKnowledge : public FreeSpaceDistances {
 public:
  double toNonConnected(const Eigen::VectorXd& /*q*/) const override {
    return std::numeric_limits<double>::infinity();
  }
  double toConnected(const Eigen::VectorXd& /*q*/) const override {
    return std::numeric_limits<double>::infinity();
  }
};

/// makeSpaceInformation() on `checker` with a copy of the planning
/// thread's metric: the threads share nothing mutable.
ob::SpaceInformationPtr spaceInformationWithMetric(const robot::RobotModel& robot,
                                                   robot::CollisionChecker& checker,
                                                   const robot::ConfigurationMetric& metric,
                                                   double resolution) {
  checker.metric().setWeights(metric.weights());
  return makeSpaceInformation(robot, checker, resolution);
}

/// What OMPL's goal sampling thread works with, shared with nobody: its
/// own collision checker (FCL objects move on every query), space
/// information for GoalLazySamples' validity check of each goal state, the
/// sampling tools (Eq. (1), Phi(h)), a generator and the decoupled sampler.
struct SamplingThreadTools {
  SamplingThreadTools(const PlanningWorld& world, const robot::Scene& scene,
                      const db::ObjectDatabase& object, const grasp::HftsSpace& space,
                      const LazyGoalSettings& settings, const WeightedStateSpace& plannerSpace,
                      double resolution)
      : checker(world.collisionModel(), scene, &object.geometry, world.collisionMesh(object.name)),
        si(spaceInformationWithMetric(world.robot(), checker, plannerSpace.metric(), resolution)),
        tools(world, scene, space, checker, settings.goals),
        rng(settings.seed),
        sampler(tools.context(rng, settings.goals, settings.smoothing.final_check),
                settings.goals.decoupled_iterations) {}

  robot::CollisionChecker checker;
  ob::SpaceInformationPtr si;
  SamplingTools tools;
  std::mt19937_64 rng;
  DecoupledGoalSampler sampler;
};

/// The goal region: OMPL's lazily sampled goal states, each the pre-grasp
/// of a goal the decoupled sampler found; remembers the goals behind them.
class LazyGraspGoal : public ob::GoalLazySamples {
 public:
  /// The thread starts with startSampling().
  explicit LazyGraspGoal(std::unique_ptr<SamplingThreadTools> tools)
      : GoalLazySamples(
            tools->si,
            [this](const ob::GoalLazySamples* /*self*/, ob::State* state) {
              return sampleNext(state);
            },
            /*autoStart=*/false),
        tools_(std::move(tools)) {}
  // The thread uses tools_: join it before they go.
  ~LazyGraspGoal() override { stopSampling(); }
  LazyGraspGoal(const LazyGraspGoal&) = delete;
  LazyGraspGoal& operator=(const LazyGraspGoal&) = delete;

  /// The goal whose pre-grasp is exactly q (RRTConnect copies goal states
  /// bit for bit), or kNone.
  GoalSample goalAt(const Eigen::VectorXd& q) const {
    const std::lock_guard<std::mutex> lock(foundMutex_);
    for (const GoalSample& g : found_)
      if (g.configuration == q) return g;
    return {};
  }

  /// The thread also stops by itself after its current step once `ptc`
  /// fires (the search's limit): joining it afterwards then costs nothing,
  /// while a path found at the limit is still being re-checked. Call
  /// before startSampling().
  void stopWhen(const ob::PlannerTerminationCondition& ptc) { deadline_ = ptc; }

  /// After stopSampling(): the thread's tools, and its exception if it died.
  const SamplingThreadTools& tools() const { return *tools_; }
  void rethrowSamplingError() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  /// OMPL's GoalSamplingFn: runs the decoupled sampler until it finds a
  /// goal (true, `state` = its pre-grasp) or sampling is stopped (false).
  bool sampleNext(ob::State* state) {
    try {
      const NoFreeSpaceKnowledge none;
      const auto stopped = [this] { return deadline_() || !isSampling(); };
      while (!stopped()) {
        GoalSample sample = tools_->sampler.sample(none, stopped);
        if (sample.kind != GoalKind::kGoal) continue;
        weightedSpace(tools_->si).fromVector(sample.configuration, state);
        const std::lock_guard<std::mutex> lock(foundMutex_);
        found_.push_back(std::move(sample));
        return true;
      }
    } catch (...) {
      error_ = std::current_exception();  // read after the join
    }
    return false;
  }

  std::unique_ptr<SamplingThreadTools> tools_;
  mutable std::mutex foundMutex_;
  std::vector<GoalSample> found_;
  std::exception_ptr error_;
  ob::PlannerTerminationCondition deadline_{ob::plannerNonTerminatingCondition()};
};

/// Stops and joins the sampling thread on every way out of solve().
class SamplingThread {
 public:
  explicit SamplingThread(LazyGraspGoal& goal) : goal_(goal) { goal_.startSampling(); }
  ~SamplingThread() { goal_.stopSampling(); }
  SamplingThread(const SamplingThread&) = delete;
  SamplingThread& operator=(const SamplingThread&) = delete;

 private:
  LazyGraspGoal& goal_;
};

/// Uniform samples from a seeded generator, counted: RRTConnect draws one
/// per iteration.
class CountingUniformSampler : public ob::RealVectorStateSampler {
 public:
  CountingUniformSampler(const ob::StateSpace* space, std::uint32_t seed, std::uint64_t& count)
      : RealVectorStateSampler(space), count_(count) {
    rng_.setLocalSeed(seed);
  }
  void sampleUniform(ob::State* state) override {
    ++count_;
    RealVectorStateSampler::sampleUniform(state);
  }

 private:
  std::uint64_t& count_;
};

/// OMPL's RRTConnect, unchanged, with its samples drawn from our seeds
/// (per instance: ompl::RNG::setSeed is process-wide and only works before
/// the first generator exists) and its tree sizes visible.
class SeededRrtConnect : public og::RRTConnect {
 public:
  SeededRrtConnect(const ob::SpaceInformationPtr& si, std::uint64_t seed)
      : RRTConnect(si), seeds_(seed) {
    rng_.setLocalSeed(static_cast<std::uint32_t>(seeds_()));
  }
  ob::PlannerStatus solve(const ob::PlannerTerminationCondition& ptc) override {
    // clear() drops the sampler: a restart gets fresh samples, not a replay.
    if (!sampler_)
      sampler_ = std::make_shared<CountingUniformSampler>(
          si_->getStateSpace().get(), static_cast<std::uint32_t>(seeds_()), samples_);
    return RRTConnect::solve(ptc);
  }
  std::uint64_t samples() const { return samples_; }
  std::uint64_t startTreeSize() const { return tStart_ ? tStart_->size() : 0; }
  std::uint64_t goalTreeSize() const { return tGoal_ ? tGoal_->size() : 0; }
  std::uint64_t goalsTaken() const { return pis_.getSampledGoalsCount(); }
  std::uint32_t nextSeed() { return static_cast<std::uint32_t>(seeds_()); }

 private:
  std::mt19937_64 seeds_;
  std::uint64_t samples_ = 0;
};

std::vector<Eigen::VectorXd> toVectors(const WeightedStateSpace& space, og::PathGeometric& path) {
  std::vector<Eigen::VectorXd> out;
  for (const ob::State* s : path.getStates()) out.push_back(space.toVector(s));
  return out;
}

/// RRTConnect's own nextGoal() would report an error when the time runs
/// out before the first goal; wait for it here instead.
void waitForFirstGoal(const LazyGraspGoal& goal, const ob::PlannerTerminationCondition& ptc) {
  while (!goal.hasStates() && goal.isSampling() && !ptc())
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

/// Runs RRTConnect until a path it finds passes smoothAndRecheck() or
/// `ptc` fires. A rejected path means starting over: the same trees would
/// find the same path again.
void searchUntilChecked(SeededRrtConnect& planner, ob::ProblemDefinition& pdef,
                        PathSmoothing smoothing, const ob::PlannerTerminationCondition& ptc,
                        LazyGoalOutcome& out) {
  const ob::SpaceInformationPtr& si = planner.getSpaceInformation();
  const WeightedStateSpace& space = weightedSpace(si);
  while (!ptc() && planner.solve(ptc) == ob::PlannerStatus::EXACT_SOLUTION) {
    const std::vector<Eigen::VectorXd> raw =
        toVectors(space, *pdef.getSolutionPath()->as<og::PathGeometric>());
    smoothing.seed = planner.nextSeed();
    PathCheckReport report;
    auto path = smoothAndRecheck(si, raw, smoothing, ptc, &report);
    out.trees.final_check_time += report.seconds;
    out.trees.certificate_queries += report.queries;
    if (path) {
      out.solved = true;
      out.path_check = report;
      out.path = std::move(*path);
      out.trees.path_length_raw = pathLength(space, raw);
      out.trees.path_length_smoothed = pathLength(space, out.path);
      return;
    }
    ++out.trees.rejected_paths;
    planner.clear();
    pdef.clearSolutionPaths();
  }
}

}  // namespace

LazyGoalRrtConnect::LazyGoalRrtConnect(ob::SpaceInformationPtr si, const PlanningWorld& world,
                                       const robot::Scene& scene, const db::ObjectDatabase& object,
                                       const grasp::HftsSpace& space, LazyGoalSettings settings)
    : si_(std::move(si)),
      world_(world),
      scene_(scene),
      object_(object),
      space_(space),
      settings_(settings) {
  weightedSpace(si_);
  if (settings_.goals.decoupled_iterations < 1)
    throw InvalidArgument("parameters.iterations", "must be >= 1");
}

LazyGoalOutcome LazyGoalRrtConnect::solve(const Eigen::VectorXd& start,
                                          const ob::PlannerTerminationCondition& ptc) {
  const WeightedStateSpace& space = weightedSpace(si_);
  const auto* validator =
      dynamic_cast<const CollisionMotionValidator*>(si_->getMotionValidator().get());
  const double resolution = validator != nullptr ? validator->resolution() : 0.02;
  auto sampling = std::make_unique<SamplingThreadTools>(world_, scene_, object_, space_, settings_,
                                                        space, resolution);
  sampling->tools.configurator.setArmReference(start.head(world_.robot().numArmDofs()));
  auto goal = std::make_shared<LazyGraspGoal>(std::move(sampling));
  auto pdef = std::make_shared<ob::ProblemDefinition>(si_);
  ob::ScopedState<> startState(si_);
  space.fromVector(start, startState.get());
  pdef->addStartState(startState);
  pdef->setGoal(goal);
  auto planner = std::make_shared<SeededRrtConnect>(si_, settings_.seed + 0x9E3779B97F4A7C15ULL);
  planner->setProblemDefinition(pdef);
  planner->setup();

  LazyGoalOutcome out;
  if (!ptc()) {  // a thread stopped before it starts makes OMPL warn
    goal->stopWhen(ptc);
    const SamplingThread thread(*goal);
    waitForFirstGoal(*goal, ptc);
    searchUntilChecked(*planner, *pdef, settings_.smoothing, ptc, out);
  }  // the sampling thread is joined here
  goal->rethrowSamplingError();
  if (out.solved) {
    out.goal = goal->goalAt(out.path.back());
    if (out.goal.kind != GoalKind::kGoal)
      throw std::logic_error("LazyGoalRrtConnect: the path ends at no sampled goal");
  }
  const SamplingThreadTools& tools = goal->tools();
  out.goals = tools.sampler.statistics();
  out.objective_evaluations = tools.tools.objective.evaluations();
  out.sampling_collision_checks = tools.checker.checkCount();
  out.trees.iterations = planner->samples();
  out.trees.goal_trees = planner->goalsTaken();
  out.trees.forward_tree_size = planner->startTreeSize();
  out.trees.backward_tree_nodes = planner->goalTreeSize();
  return out;
}

}  // namespace hfts::planner
