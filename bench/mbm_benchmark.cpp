#include "mbm_benchmark.h"

#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/util/Console.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <map>
#include <ostream>
#include <sstream>

#include "core/atomic_file.h"
#include "planner/grasp_motion_planner.h"
#include "planner/parameters.h"
#include "planner/plan_settings.h"
#include "robot/collision_checker.h"
#include "robot/collision_model.h"
#include "robot/moveit_problem.h"

namespace hfts::bench {

namespace fs = std::filesystem;
namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point began) {
  return std::chrono::duration<double>(Clock::now() - began).count();
}

/// One run of one algorithm on one problem.
struct MbmRun {
  std::string scenario, problem, algorithm;
  bool solved = false;
  std::string reason;  ///< why not ("none" when solved)
  double time = 0.0;   ///< s: what the caller waits for (set-up, search, smoothing, checks)
  /// s, part of time: smoothing and the final check (the multi-tree
  /// planner's smoothing_time; rrtconnect's simplification and dense check)
  double smoothing = 0.0;
  /// s, part of smoothing: the final check of the returned path (and of
  /// the paths a repair compared); rrtconnect's dense check
  double final_check = 0.0;
  std::size_t waypoints = 0;
  double length = 0.0;  ///< rad: sum of the segments' Euclidean joint distances
  std::uint64_t collision_checks = 0;
};

double lengthOf(const std::vector<Eigen::VectorXd>& path) {
  double l = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) l += (path[i] - path[i - 1]).norm();
  return l;
}

/// A uniform sampler seeded by us (OMPL's generators are seeded process-wide).
class SeededSampler : public ob::RealVectorStateSampler {
 public:
  SeededSampler(const ob::StateSpace* space, std::uint32_t seed) : RealVectorStateSampler(space) {
    rng_.setLocalSeed(seed);
  }
};

/// OMPL's path simplifier with its random choices seeded by us: with
/// OMPL's process-wide seed the simplified path, and so whether it passes
/// the dense check, changed from run to run.
class SeededPathSimplifier : public og::PathSimplifier {
 public:
  SeededPathSimplifier(const ob::SpaceInformationPtr& si, std::uint32_t seed) : PathSimplifier(si) {
    rng_.setLocalSeed(seed);
  }
};

/// OMPL's RRTConnect with its default range and FCL alone (no sphere tier)
/// as the state validity checker, held to the multi-tree planner's
/// contract: OMPL's discrete motion validator at the planner's tree
/// resolution (collision_resolution), OMPL's path simplification (seeded),
/// then the path sampled at the planner's final resolution
/// (final_resolution); a path that fails that is no solution
/// ("dense_check_failed").
MbmRun rrtConnect(const robot::RobotModel& robot, const robot::CollisionModel& model,
                  const robot::MoveItProblem& p, double timeLimit, std::uint64_t seed) {
  MbmRun run;
  const auto began = Clock::now();
  robot::CollisionChecker checker(model, p.scene, nullptr);
  checker.setSphereTier(false);
  const int n = robot.numDofs();
  auto space = std::make_shared<ob::RealVectorStateSpace>(static_cast<unsigned>(n));
  ob::RealVectorBounds bounds(static_cast<unsigned>(n));
  for (int d = 0; d < n; ++d) {
    bounds.setLow(static_cast<unsigned>(d), robot.lowerLimits()(d));
    bounds.setHigh(static_cast<unsigned>(d), robot.upperLimits()(d));
  }
  space->setBounds(bounds);
  std::uint32_t samplerSeed = static_cast<std::uint32_t>(seed);
  space->setStateSamplerAllocator([&samplerSeed](const ob::StateSpace* s) {
    return std::make_shared<SeededSampler>(s, samplerSeed++);
  });
  og::SimpleSetup setup(space);
  Eigen::VectorXd q(n);
  setup.setStateValidityChecker([&](const ob::State* state) {
    const auto* v = state->as<ob::RealVectorStateSpace::StateType>();
    for (int d = 0; d < n; ++d) q(d) = v->values[d];
    return !checker.inCollision(q);
  });
  ob::ScopedState<> start(space), goal(space);
  for (int d = 0; d < n; ++d) {
    start[static_cast<unsigned>(d)] = p.start(d);
    goal[static_cast<unsigned>(d)] = p.goal(d);
  }
  setup.setStartAndGoalStates(start, goal);
  const planner::PlanSettings settings = planner::defaultSettings(robot);
  setup.getSpaceInformation()->setStateValidityCheckingResolution(
      settings.execution.collision_resolution / space->getMaximumExtent());
  setup.setPlanner(std::make_shared<og::RRTConnect>(setup.getSpaceInformation()));
  const ob::PlannerStatus status = setup.solve(std::max(0.0, timeLimit - since(began)));
  run.solved = status == ob::PlannerStatus::EXACT_SOLUTION;
  run.reason = run.solved ? "none" : status.asString();
  if (run.solved) {
    const auto simplifying = Clock::now();
    og::PathGeometric& path = setup.getSolutionPath();
    SeededPathSimplifier(setup.getSpaceInformation(), static_cast<std::uint32_t>(seed))
        .simplify(path, ob::plannerNonTerminatingCondition());
    std::vector<Eigen::VectorXd> states;
    for (const ob::State* s : path.getStates()) {
      const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
      states.push_back(Eigen::Map<const Eigen::VectorXd>(v->values, n));
    }
    run.waypoints = states.size();
    run.length = lengthOf(states);
    // Sampled as the planner's final check samples (its Eq. (3) metric).
    const auto checking = Clock::now();
    if (checker.validSegments(states, settings.execution.final_resolution) + 1 != states.size()) {
      run.solved = false;
      run.reason = "dense_check_failed";
    }
    run.final_check = since(checking);
    run.smoothing = since(simplifying);
  }
  run.time = since(began);
  run.collision_checks = checker.checkCount();
  return run;
}

/// The multi-tree planner towards the problem's joint goal, as a plan
/// request with `goals` (planner::planGrasp).
MbmRun multiTree(const planner::PlanningWorld& world, const Algorithm& algorithm,
                 const robot::MoveItProblem& p, double timeLimit, std::uint64_t seed) {
  planner::PlanRequest r;
  r.scene = p.scene;
  r.start = p.start;
  r.goals = {planner::JointGoal{p.goal}};
  r.time_limit = timeLimit;
  r.seed = seed;
  r.trajectory_rate = 0.0;
  r.preset = algorithm.preset;
  r.parameters = algorithm.parameters;
  const planner::PlanResult result = planner::planGrasp(world, r);
  MbmRun run;
  run.solved = result.success;
  run.reason = planner::toString(result.failure);
  run.time = result.stats.planning_time;
  run.waypoints = result.path.size();
  run.length = lengthOf(result.path);
  run.collision_checks = result.stats.collision_checks;
  run.smoothing = result.stats.smoothing_time;
  run.final_check = result.stats.final_check_time;
  return run;
}

std::string csvOf(const std::vector<MbmRun>& runs) {
  std::ostringstream out;
  out << "scenario,problem,algorithm,solved,reason,time,smoothing_time,final_check_time,waypoints,"
         "path_length,collision_checks\n"
      << std::setprecision(9);
  for (const MbmRun& r : runs)
    out << r.scenario << "," << r.problem << "," << r.algorithm << "," << (r.solved ? 1 : 0) << ","
        << r.reason << "," << r.time << "," << r.smoothing << "," << r.final_check << ","
        << r.waypoints << "," << r.length << "," << r.collision_checks << "\n";
  return out.str();
}

/// Nearest-rank quantile of sorted values.
double quantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return std::nan("");
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(sorted.size())));
  return sorted[std::min(sorted.size() - 1, rank == 0 ? 0 : rank - 1)];
}

struct Summary {
  std::size_t runs = 0, solved = 0;
  std::vector<double> times;   ///< of the solved runs, sorted
  std::vector<double> search;  ///< the same without smoothing, sorted
};

void printTable(const std::vector<MbmRun>& runs, const std::vector<std::string>& algorithms,
                std::ostream& out) {
  std::map<std::pair<std::string, std::string>, Summary> by;
  std::vector<std::string> scenarios;
  for (const MbmRun& r : runs) {
    for (const std::string& key : {r.scenario, std::string("all")}) {
      Summary& s = by[{key, r.algorithm}];
      ++s.runs;
      if (!r.solved) continue;
      ++s.solved;
      s.times.push_back(r.time);
      s.search.push_back(r.time - r.smoothing);
    }
    if (std::find(scenarios.begin(), scenarios.end(), r.scenario) == scenarios.end())
      scenarios.push_back(r.scenario);
  }
  scenarios.push_back("all");
  out << std::left << std::setw(26) << "scenario" << std::setw(28) << "algorithm"
      << "solved     median ms   p95 ms    max ms  median w/o smoothing ms\n"
      << std::fixed;
  for (const std::string& scenario : scenarios)
    for (const std::string& algorithm : algorithms) {
      Summary& s = by[{scenario, algorithm}];
      std::sort(s.times.begin(), s.times.end());
      std::sort(s.search.begin(), s.search.end());
      out << std::left << std::setw(26) << scenario << std::setw(28) << algorithm << std::right
          << std::setw(4) << s.solved << "/" << std::left << std::setw(5) << s.runs << std::right
          << std::setprecision(3) << std::setw(11) << 1e3 * quantile(s.times, 0.5) << std::setw(9)
          << 1e3 * quantile(s.times, 0.95) << std::setw(10) << 1e3 * quantile(s.times, 1.0)
          << std::setw(25) << 1e3 * quantile(s.search, 0.5) << "\n";
    }
}

}  // namespace

std::vector<MbmProblemFiles> findMbmProblems(const fs::path& dir,
                                             const std::vector<std::string>& scenarios,
                                             int perScenario) {
  if (!fs::is_directory(dir)) throw UsageError("--mbm: '" + dir.string() + "' is not a folder");
  std::vector<std::string> folders;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_directory()) folders.push_back(e.path().filename().string());
  std::sort(folders.begin(), folders.end());
  requireKnown(scenarios, folders, "scenario");
  std::vector<MbmProblemFiles> out;
  for (const std::string& scenario : scenarios.empty() ? folders : scenarios) {
    std::vector<MbmProblemFiles> found;
    for (const auto& e : fs::directory_iterator(dir / scenario)) {
      const std::string file = e.path().filename().string();
      if (file.rfind("scene", 0) != 0 || e.path().extension() != ".yaml") continue;
      const std::string name = e.path().stem().string().substr(5);
      const fs::path request = dir / scenario / ("request" + name + ".yaml");
      if (!fs::exists(request))
        throw UsageError("--mbm: " + e.path().string() + " has no request" + name + ".yaml");
      found.push_back({scenario, name, e.path(), request});
    }
    if (found.empty())
      throw UsageError("--mbm: no sceneNNNN.yaml in '" + (dir / scenario).string() + "'");
    std::sort(found.begin(), found.end(),
              [](const auto& a, const auto& b) { return a.name < b.name; });
    if (perScenario > 0 && found.size() > static_cast<std::size_t>(perScenario))
      found.resize(static_cast<std::size_t>(perScenario));
    out.insert(out.end(), found.begin(), found.end());
  }
  return out;
}

int runMbm(const MbmOptions& o, std::ostream& out) {
  checkRunsAndTimeLimit(1, o.time_limit);
  if (o.problems < 0) throw UsageError("--problems must be >= 0");
  const std::vector<Algorithm> algorithms = parseAlgorithms(o.algorithms);
  for (const Algorithm& a : algorithms)
    if (a.algorithm == planner::PlanAlgorithm::kDecoupled)
      throw UsageError("--mbm: '" + a.name + "': motion goals take coupled, paper or rrtconnect");
  const std::vector<MbmProblemFiles> problems = findMbmProblems(o.dir, o.scenarios, o.problems);
  planner::quietOmpl();
  // The baseline's simplifier warns of paths that touch invalid states;
  // the CSV's reasons say what failed.
  ompl::msg::setLogLevel(ompl::msg::LOG_NONE);
  const planner::PlanningWorld world(
      robot::RobotModel::load(o.robot),
      std::make_shared<const planner::ObjectLibrary>(std::map<std::string, db::ObjectDatabase>{}));
  const robot::RobotModel& robot = world.robot();
  std::vector<MbmRun> runs;
  bool warned = false;
  for (const MbmProblemFiles& files : problems) {
    const robot::MoveItProblem p = robot::loadMoveItProblem(robot, files.scene, files.request);
    if (!p.stricter_pairs.empty() && !warned) {
      warned = true;
      out << "note: " << files.scenario << "/" << files.name << " allows "
          << p.stricter_pairs.size() << " link pairs the model checks (first "
          << p.stricter_pairs.front().first << " - " << p.stricter_pairs.front().second << ")\n";
    }
    for (const Algorithm& a : algorithms) {
      MbmRun run = a.algorithm == planner::PlanAlgorithm::kRrtConnect
                       ? rrtConnect(robot, world.collisionModel(), p, o.time_limit, o.seed)
                       : multiTree(world, a, p, o.time_limit, o.seed);
      run.scenario = files.scenario;
      run.problem = files.name;
      run.algorithm = a.name;
      runs.push_back(std::move(run));
      if (!o.csv.empty()) core::writeFileAtomically(o.csv, csvOf(runs));
    }
  }
  printTable(runs, o.algorithms, out);
  return 0;
}

}  // namespace hfts::bench
