#pragma once
// Algorithm 1 on its own: a goal sampler that hands out scripted answers,
// the multi-tree planner on a scene of boxes built in code, and a
// termination condition that records the planner's statistics at the start
// of every iteration. Include only where OMPL is used.

#include <gtest/gtest.h>

#include <ompl/base/PlannerData.h>
#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/util/Console.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "planner/configuration_space.h"
#include "planner/multi_tree_cbirrt.h"
#include "planner/parameters.h"
#include "robot/collision_checker.h"
#include "robot_fixture.h"

namespace hfts::test {

/// SAMPLEGOAL replaced by a script: call i returns answer i, every later
/// call kNone. Each call also records Omega and Gamma of the probe
/// configurations, once plainly and once through a memo kept across calls
/// (as the goal hierarchy cache keeps one per cached configuration).
class ScriptedGoalSampler : public planner::GoalSampler {
 public:
  struct Look {
    planner::FreeSpaceDistance plain, memoised;
  };

  explicit ScriptedGoalSampler(std::vector<planner::GoalSample> script)
      : script_(std::move(script)) {}

  planner::GoalSample sample(const planner::FreeSpaceDistances& knowledge,
                             const std::function<bool()>& /*stop*/) override {
    std::vector<Look>& looks = seen_.emplace_back();
    for (Probe& p : probes_)
      looks.push_back({{knowledge.toNonConnected(p.q), knowledge.toConnected(p.q)},
                       knowledge.distances(p.q, p.memo)});
    const std::uint64_t call = stats_.calls++;
    if (call >= script_.size()) return {};
    const planner::GoalSample& answer = script_[call];
    if (answer.kind == planner::GoalKind::kGoal) ++stats_.valid_goals;
    if (answer.kind == planner::GoalKind::kApproximate) ++stats_.approximate_goals;
    return answer;
  }

  void addProbe(const Eigen::VectorXd& q) { probes_.push_back({q, {}}); }
  /// seen()[call][probe]: what the planner told the sampler at that call.
  const std::vector<std::vector<Look>>& seen() const { return seen_; }

 private:
  struct Probe {
    Eigen::VectorXd q;
    planner::FreeSpaceMemo memo;
  };
  std::vector<planner::GoalSample> script_;
  std::vector<Probe> probes_;
  std::vector<std::vector<Look>> seen_;
};

inline planner::GoalSample scripted(planner::GoalKind kind, const Eigen::VectorXd& q) {
  planner::GoalSample s;
  s.kind = kind;
  s.configuration = q;
  if (kind == planner::GoalKind::kGoal) s.grasp = q;
  return s;
}

inline robot::Obstacle box(const std::string& name, const Eigen::Vector3d& size,
                           const Eigen::Vector3d& centre) {
  robot::Obstacle b;
  b.name = name;
  b.type = robot::Obstacle::Type::kBox;
  b.size = size;
  b.pose.translation() = centre;
  return b;
}

/// The KR5 + SDH with arm joints 1-6 and the hand open.
inline Eigen::VectorXd armAt(double a1, double a2, double a3, double a4, double a5, double a6) {
  Eigen::VectorXd q = kr5Sdh().home();
  // (Also tells GCC, -Wnull-dereference, that q is not empty.)
  if (q.size() < 6) throw std::logic_error("armAt: not the KR5");
  const double arm[] = {a1, a2, a3, a4, a5, a6};
  q.head<6>() = Eigen::Map<const Eigen::Matrix<double, 6, 1>>(arm);
  return q;
}

/// The multi-tree planner on `scene` (no target object) from `start`, its
/// goal the scripted sampler, set up as planGrasp does.
struct StubProblem {
  StubProblem(robot::Scene s, const Eigen::VectorXd& start, std::vector<planner::GoalSample> script)
      : scene(std::move(s)),
        checker(test::collisionOf(kr5Sdh()), scene, nullptr),
        si(planner::makeSpaceInformation(kr5Sdh(), checker, 0.05)),
        sampler(std::move(script)),
        planner(std::make_shared<planner::MultiTreeCBiRRT>(si)),
        pdef(std::make_shared<ompl::base::ProblemDefinition>(si)) {
    ompl::base::ScopedState<> from(si);
    planner::weightedSpace(si).fromVector(start, from.get());
    pdef->addStartState(from);
    pdef->setGoal(std::make_shared<planner::GraspGoal>(si, sampler));
    planner->setProblemDefinition(pdef);
  }

  /// A planner parameter by its declared name; throws InvalidArgument for a
  /// rejected one.
  void set(const std::string& name, double value) {
    std::ostringstream text;
    text.precision(17);
    text << value;
    // (OMPL reports every parameter it sets at its debug level.)
    const ompl::msg::LogLevel level = ompl::msg::getLogLevel();
    ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
    try {
      planner::setParameter(planner->params(), name, text.str());
    } catch (...) {
      ompl::msg::setLogLevel(level);
      throw;
    }
    ompl::msg::setLogLevel(level);
  }
  void set(std::initializer_list<std::pair<const char*, double>> parameters) {
    for (const auto& [name, value] : parameters) set(name, value);
  }

  robot::Scene scene;
  robot::CollisionChecker checker;
  ompl::base::SpaceInformationPtr si;
  ScriptedGoalSampler sampler;
  std::shared_ptr<planner::MultiTreeCBiRRT> planner;
  ompl::base::ProblemDefinitionPtr pdef;
};

/// Backward trees in B_G and B_A (Algorithm 1): added, and not yet merged
/// into T_f or dropped after a failed re-check.
inline std::uint64_t liveTrees(const planner::TreeStatistics& s) {
  return s.goal_trees + s.approximate_trees - s.merged_trees - s.rejected_paths;
}

/// Algorithm 1 line 6 observed: solve() polls its termination condition at
/// the start of every iteration (and during tree extensions). The last poll
/// before the iteration counter grows sees what line 8 of the next
/// iteration sees, so after(i) holds the planner's statistics and the
/// sampler's call count once i iterations are done. Stops the planner after
/// `iterations` iterations, or earlier when `stop` says so.
class IterationLog {
 public:
  struct Snapshot {
    planner::TreeStatistics stats;
    std::uint64_t sampler_calls = 0;
  };

  IterationLog(const planner::MultiTreeCBiRRT& planner, const planner::GoalSampler& sampler,
               std::uint64_t iterations, std::function<bool(const Snapshot&)> stop = {})
      : planner_(planner), sampler_(sampler), limit_(iterations), stop_(std::move(stop)) {}

  ompl::base::PlannerTerminationCondition condition() {
    return ompl::base::PlannerTerminationCondition([this] { return poll(); });
  }
  /// Iterations done (when the planner stopped at the termination condition).
  std::uint64_t iterations() const { return after_.empty() ? 0 : after_.size() - 1; }
  const Snapshot& after(std::uint64_t i) const { return after_.at(i); }
  /// Whether iteration i (from 1) called the goal sampler.
  bool sampled(std::uint64_t i) const {
    return after(i).sampler_calls != after(i - 1).sampler_calls;
  }

 private:
  bool poll() {
    const std::uint64_t i = planner_.statistics().iterations;
    if (after_.size() <= i) after_.resize(i + 1);
    after_[i] = {planner_.statistics(), sampler_.statistics().calls};
    return i >= limit_ || (stop_ && stop_(after_[i]));
  }

  const planner::MultiTreeCBiRRT& planner_;
  const planner::GoalSampler& sampler_;
  std::uint64_t limit_;
  std::function<bool(const Snapshot&)> stop_;
  std::vector<Snapshot> after_;
};

/// The vertices' configurations, by vertex index.
inline std::vector<Eigen::VectorXd> vertexConfigurations(const ompl::base::PlannerData& data) {
  const planner::WeightedStateSpace& space = planner::weightedSpace(data.getSpaceInformation());
  std::vector<Eigen::VectorXd> out;
  for (unsigned v = 0; v < data.numVertices(); ++v)
    out.push_back(space.toVector(data.getVertex(v).getState()));
  return out;
}

/// The index of the vertex at q, or PlannerData::INVALID_INDEX.
inline unsigned vertexAt(const std::vector<Eigen::VectorXd>& vertices, const Eigen::VectorXd& q) {
  for (unsigned v = 0; v < vertices.size(); ++v)
    if (vertices[v] == q) return v;
  return ompl::base::PlannerData::INVALID_INDEX;
}

/// |observed - n p| within 4.5 standard deviations of Binomial(n, p); exact
/// for p = 0 or 1.
inline void expectBinomial(std::uint64_t observed, std::uint64_t n, double p,
                           const std::string& what) {
  const double mean = static_cast<double>(n) * p;
  EXPECT_NEAR(static_cast<double>(observed), mean, 4.5 * std::sqrt(mean * (1.0 - p)) + 1e-9)
      << what << ": " << observed << " of " << n << ", p = " << p;
}

}  // namespace hfts::test
