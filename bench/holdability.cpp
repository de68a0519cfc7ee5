// bench::holdability (holdability.h): can the robot hold the object where
// it stands at all? Used by hfts-bench to list the cases. Built on the
// planner's own problem set-up (planner/src/plan_problem.h), so that it
// asks exactly what a plan would.
#include "holdability.h"

#include <algorithm>
#include <random>
#include <sstream>
#include <unordered_set>
#include <vector>

#include "grasp/grasp_optimizer.h"
#include "grasp/grasp_quality.h"
#include "plan_problem.h"
#include "planner/sampling_tools.h"

namespace hfts::bench {

using planner::PlanFailure;

namespace {

/// The hand alone at `palm` (world frame): pre-grasp, closing motion and
/// grasp clear (holdability's criterion).
bool handFits(robot::CollisionChecker& checker, const Eigen::Isometry3d& palm,
              const Eigen::VectorXd& pregrasp, const Eigen::VectorXd& grasp) {
  if (checker.handInCollision(palm, pregrasp, robot::CollisionRequest{})) return false;
  // The closing motion, its last state the grasp.
  constexpr int kClosingSteps = 8;
  for (int k = 1; k <= kClosingSteps; ++k) {
    const double t = static_cast<double>(k) / kClosingSteps;
    if (checker.handInCollision(palm, pregrasp + t * (grasp - pregrasp),
                                robot::CollisionRequest::grasp()))
      return false;
  }
  return true;
}

}  // namespace

Holdability holdability(const planner::PlanningWorld& world, const planner::PlanRequest& request,
                        int climbs) {
  if (climbs < 1) throw InvalidArgument("climbs", "must be at least 1");
  planner::quietOmpl();
  Holdability out;
  const std::string name = planner::objectNameOf(request);
  const db::ObjectDatabase* object = world.object(name);
  if (object == nullptr) {
    out.reason = "unknown object '" + name + "'";
    return out;
  }
  const planner::SharedProblem shared(world, *object, request);
  planner::Problem p(shared, request.seed, planner::startOf(world.robot(), request));
  auto cannot = planner::checkTarget(p);
  if (cannot.first == PlanFailure::kNone) cannot = planner::checkReach(p);
  if (cannot.first == PlanFailure::kNone) cannot = planner::checkGraspable(p);
  if (cannot.first != PlanFailure::kNone) {
    out.reason = cannot.second;
    return out;
  }
  // The question is whether any grasp exists: the objective ranks grasps
  // whose hand meets an obstacle last.
  planner::GoalSamplingSettings settings = p.goals;
  settings.hand_clearance = 1;
  planner::SamplingTools tools(world, p.scene, p.space, p.checker, settings);
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
      if (p.checker.handInCollision(p.scene.target_pose * palm, pregrasp,
                                    robot::CollisionRequest{}))
        continue;
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

}  // namespace hfts::bench
