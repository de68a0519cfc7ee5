#include "plan_search.h"

#include <ompl/base/ProblemDefinition.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <set>

#include "carry_planning.h"
#include "planner/backward_projection.h"
#include "planner/lazy_goal_baseline.h"
#include "planner/sampling_tools.h"

namespace hfts::planner {

namespace {

/// The goal check of physics_check: the reached goal's grasp simulated
/// (its verdict kept for the result). A grasp that failed is not simulated
/// again for another arm configuration with the same closed hand. The
/// simulations are counted and timed in `out.stats`.
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
    const auto begin = std::chrono::steady_clock::now();
    // The goal's lift (goalCheck plans it first) is the one simulated.
    physics::GraspVerdict verdict =
        physics::simulateGrasp(p.world.collisionModel(), p.scene, p.object, goal.configuration,
                               goal.grasp, options, out.lift ? &out.lift->path : nullptr);
    ++out.stats.physics_checks;
    out.stats.physics_time +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    if (!verdict.held) {
      failed->insert(goal.closure.get());
      return false;
    }
    out.verdict = std::move(verdict);
    return true;
  };
}

/// What a reached goal must pass before it ends the search, cheapest
/// first: with certify_path its closing motion proven free (the closing
/// rule; a goal refused counts as closing_blocked), with a lift a free
/// lift (lift_blocked), then with physics_check its grasp holding in
/// physics. None when nothing is asked for. Each stops with the search's
/// time limit: a goal whose checks the limit cut short is refused, and
/// not counted as blocked.
MultiTreeCBiRRT::GoalCheck goalCheck(Problem& p, SearchOutcome& out,
                                     const ob::PlannerTerminationCondition& ptc) {
  MultiTreeCBiRRT::GoalCheck physics =
      p.settings.goal.physics_check ? physicsGoalCheck(p, out, ptc) : MultiTreeCBiRRT::GoalCheck{};
  const MotionCheck& check = p.planner->smoothing().final_check;
  if (!check.certifies() && !p.lift) return physics;
  return [&p, &out, &check, &ptc, physics = std::move(physics)](const GoalSample& goal) {
    if (check.certifies()) {
      const MotionVerdict closing = checkMotion(p.checker, check, {goal.configuration, goal.grasp},
                                                robot::CertifyRule::kClosing);
      out.stats.certificate_queries += closing.queries;
      if (!closing.free) {
        ++out.stats.rejected.closing_blocked;
        return false;
      }
    }
    if (p.lift) {
      out.lift = liftOf(p, goal, out.stats, ptc);
      if (!out.lift) {
        if (!ptc()) ++out.stats.rejected.lift_blocked;
        return false;
      }
    }
    return !physics || physics(goal);
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

}  // namespace

std::optional<LiftPath> liftOf(const Problem& p, const GoalSample& goal, PlanStatistics& stats,
                               const ob::PlannerTerminationCondition& ptc, std::string* why) {
  const Hold hold = holdObject(p.world.collisionModel(), p.scene.robot_base, p.object.geometry,
                               p.object.name, p.scene.target_pose, goal.grasp);
  std::size_t queries = 0;
  std::optional<LiftPath> lift =
      planLift(hold, p.scene, goal.grasp, p.lift->height, p.planner->smoothing().final_check, why,
               &queries, [&ptc] { return ptc(); });
  stats.certificate_queries += queries;
  if (!lift && !ptc()) lift = plannedLift(p, hold, goal.grasp, p.lift->height, ptc);
  return lift;
}

/// The multi-tree CBiRRT (Algorithm 1) with the coupled goal sampler
/// (Algorithm 2) or the decoupled one.
SearchOutcome searchMultiTree(Problem& p, bool coupled,
                              const ob::PlannerTerminationCondition& ptc) {
  MultiTreeCBiRRT& planner = *p.planner;
  SamplingTools tools(p.world, p.scene, p.space, p.checker, p.goals);
  tools.configurator.setArmReference(p.start.head(p.world.robot().numArmDofs()));
  // The closing motion of a goal the trees reach is proven in the goal
  // check below, not for every goal candidate the sampler makes.
  MotionCheck sampledClosing = planner.smoothing().final_check;
  sampledClosing.bound = nullptr;
  const std::unique_ptr<GraspGoalSampler> sampler =
      tools.makeSampler(coupled, planner.rng(), p.goals, sampledClosing);
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
  planner.setGoalCheck(goalCheck(p, out, ptc));
  out.solved = planner.solve(ptc) == ob::PlannerStatus::EXACT_SOLUTION;
  out.goals = sampler->statistics();
  const PlanStatistics checked = out.stats;  // the goal checks' counts
  out.stats = planStatistics(planner.statistics(), out.goals, tools.objective.evaluations(),
                             p.checker.checkCount());
  out.stats.physics_checks = checked.physics_checks;
  out.stats.physics_time = checked.physics_time;
  out.stats.certificate_queries += checked.certificate_queries;
  out.stats.rejected.closing_blocked += checked.rejected.closing_blocked;
  out.stats.rejected.lift_blocked += checked.rejected.lift_blocked;
  if (const auto* hfts = dynamic_cast<const HftsGoalSampler*>(sampler.get());
      hfts != nullptr && p.explored)
    out.explored = exploredNodes(hfts->cache(), tools);
  if (out.solved) {
    out.path = planner.solutionPath();
    out.path_check = planner.pathCheck();
    out.goal = planner.reachedGoal();
  }
  return out;
}

/// The outside baseline: OMPL's RRTConnect towards lazily sampled
/// decoupled goals.
SearchOutcome searchBaseline(Problem& p, const ob::PlannerTerminationCondition& ptc) {
  LazyGoalRrtConnect baseline(p.si, p.world, p.scene, p.object, p.space,
                              {p.goals, p.planner->smoothing(), p.seed});
  LazyGoalOutcome found = baseline.solve(p.start, ptc);
  SearchOutcome out;
  out.solved = found.solved;
  out.path = std::move(found.path);
  out.path_check = found.path_check;
  out.goal = std::move(found.goal);
  out.goals = found.goals;
  out.stats = planStatistics(found.trees, found.goals, found.objective_evaluations,
                             p.checker.checkCount() + found.sampling_collision_checks);
  return out;
}

}  // namespace hfts::planner
