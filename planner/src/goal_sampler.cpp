#include "planner/goal_sampler.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/invalid_argument.h"
#include "grasp/grasp_quality.h"
#include "with_approximate_goals.h"

namespace hfts::planner {

GraspGoalSampler::GraspGoalSampler(GoalSamplingContext context) : context_(context) {
  if (context.space == nullptr || context.objective == nullptr || context.configurator == nullptr ||
      context.checker == nullptr || context.rng == nullptr)
    throw std::invalid_argument("GoalSamplingContext: a tool is missing (null)");
  if (!(context.closing.resolution > 0.0))
    throw InvalidArgument("GoalSamplingContext::closing", "resolution must be > 0");
  if (!(context.max_fingertip_error > 0.0))
    throw InvalidArgument("parameters.max_fingertip_error", "must be > 0");
  if (!(context.min_epsilon >= 0.0))
    throw InvalidArgument("parameters.min_epsilon", "must be >= 0");
}

std::vector<CachedConfiguration> GraspGoalSampler::configurationsOf(const grasp::HftsNode& node,
                                                                    double epsilon,
                                                                    bool* otherHandsSampled) {
  const bool leaf = context_.space->isLeaf(node);
  // A leaf without force closure is never a goal: one palm pose gives its
  // configuration for the rating and A; the palm turns are for the grasps
  // that may be goals and the inner nodes above them.
  const bool turn = !leaf || epsilon > 0.0;
  // Only a stable leaf can be a goal: only its hand is closed on the object.
  const bool close = leaf && epsilon > 0.0;
  std::vector<grasp::GraspConfigurations> postures{
      context_.configurator->configure(*context_.space, node, *context_.rng, turn, close)};
  ++stats_.configured_nodes;
  if (turn && postures.front().hand.free_turn) ++stats_.turned_nodes;
  std::vector<CachedConfiguration> free, colliding;
  label(node, epsilon, postures.front(), free, colliding);
  const auto isGoal = [](const CachedConfiguration& c) { return c.goal; };
  if (context_.other_postures && leaf && epsilon > 0.0 &&
      std::none_of(free.begin(), free.end(), isGoal)) {
    // The first posture gives no goal: try the hand's other ways of taking
    // the same contacts (another finger on a contact, the palm turned).
    // postures grows only after the call has read its first posture.
    for (grasp::GraspConfigurations& other : context_.configurator->configureOtherHands(
             context_.space->representative(node), postures.front().hand,
             context_.max_fingertip_error, *context_.rng, close)) {
      label(node, epsilon, other, free, colliding);
      postures.push_back(std::move(other));
    }
    if (otherHandsSampled != nullptr) *otherHandsSampled = true;
  }
  if (!free.empty() || !colliding.empty()) ++stats_.kinematic_solutions;
  if (leaf) countRejection(epsilon, postures, free);
  // C_n holds the free configurations, or else one colliding configuration
  // (Sec. III-B.3): it still tells how close the grasp is to C_free. One,
  // as in the paper: the best of all IK branches would rate a grasp that
  // collides everywhere by its luckiest branch, steering the search into
  // colliding branches (measured: 1-5 % of leaves collision-free instead
  // of 10-25 %, docs/results.md).
  if (!free.empty() || colliding.empty()) return free;
  const std::size_t pick =
      std::uniform_int_distribution<std::size_t>(0, colliding.size() - 1)(*context_.rng);
  return {std::move(colliding[pick])};
}

std::vector<CachedConfiguration> GraspGoalSampler::otherHandConfigurationsOf(
    const grasp::HftsNode& node, double epsilon) {
  std::vector<CachedConfiguration> free, colliding;
  const bool close = context_.space->isLeaf(node) && epsilon > 0.0;
  for (const grasp::GraspConfigurations& posture : context_.configurator->configureOtherHands(
           context_.space->representative(node), context_.max_fingertip_error, *context_.rng,
           close))
    label(node, epsilon, posture, free, colliding);
  return free;
}

void GraspGoalSampler::label(const grasp::HftsNode& node, double epsilon,
                             const grasp::GraspConfigurations& all,
                             std::vector<CachedConfiguration>& free,
                             std::vector<CachedConfiguration>& colliding) {
  const bool stableLeaf = context_.space->isLeaf(node) && epsilon > 0.0;
  std::vector<char> goals(all.configurations.size(), 0);
  // One closure per palm pose, shared by its arm solutions: rate it once.
  const grasp::HandClosure* rated = nullptr;
  double contactEpsilon = 0.0;
  for (std::size_t k = 0; k < all.configurations.size(); ++k) {
    const grasp::GraspConfiguration& c = all.configurations[k];
    if (c.label == grasp::ConfigurationLabel::kNoKinematicSolution) continue;
    CachedConfiguration out;
    out.pregrasp = c.pregrasp;
    out.grasp = c.grasp;
    out.fingertip_error = c.fingertip_error;
    out.closure = c.closure;
    out.collision_free = c.label == grasp::ConfigurationLabel::kCollisionFree;
    if (c.closure && c.closure.get() != rated) {
      rated = c.closure.get();
      contactEpsilon = c.closure->touches() ? contactQuality(*c.closure) : 0.0;
    }
    out.contact_epsilon = c.closure ? contactEpsilon : 0.0;
    // A whole-turn variant closes the hand where its twin does.
    out.goal = c.same_poses_as >= 0 ? goals[static_cast<std::size_t>(c.same_poses_as)] != 0
                                    : out.collision_free && stableLeaf && isGoal(out);
    goals[k] = out.goal ? 1 : 0;
    (out.collision_free ? free : colliding).push_back(std::move(out));
  }
}

double GraspGoalSampler::contactQuality(const grasp::HandClosure& closure) const {
  return grasp::graspQuality(grasp::qualityRequest(*context_.space, closure.contacts(),
                                                   context_.objective->options()))
      .epsilon;
}

bool GraspGoalSampler::isGoal(const CachedConfiguration& c) {
  return c.closure && c.closure->touches() && c.contact_epsilon >= context_.min_epsilon &&
         c.contact_epsilon > 0.0 && c.fingertip_error <= context_.max_fingertip_error &&
         context_.checker->isMotionValid(c.pregrasp, c.grasp, context_.closing.resolution,
                                         robot::CollisionRequest::grasp()) &&
         closingProven(c);
}

bool GraspGoalSampler::closingProven(const CachedConfiguration& c) {
  if (!context_.closing.certifies()) return true;
  const MotionVerdict verdict = checkMotion(*context_.checker, context_.closing,
                                            {c.pregrasp, c.grasp}, robot::CertifyRule::kClosing);
  stats_.certificate_queries += verdict.queries;
  return verdict.free;
}

void GraspGoalSampler::countRejection(double epsilon,
                                      const std::vector<grasp::GraspConfigurations>& postures,
                                      const std::vector<CachedConfiguration>& free) {
  GraspRejections& r = stats_.rejected;
  const double tolerance = context_.max_fingertip_error;
  const auto reaches = [tolerance](const auto& c) { return c.fingertip_error <= tolerance; };
  const auto any = [&](auto&& predicate) {
    for (const grasp::GraspConfigurations& p : postures)
      for (const grasp::GraspConfiguration& c : p.configurations)
        if (c.label != grasp::ConfigurationLabel::kNoKinematicSolution && predicate(c)) return true;
    return false;
  };
  if (!(epsilon > 0.0))
    ++r.unstable;
  else if (!any([](const grasp::GraspConfiguration&) { return true; }))
    ++r.no_arm_ik;
  else if (!any(reaches))
    ++r.out_of_hand_reach;
  else if (std::none_of(free.begin(), free.end(), reaches))
    ++r.colliding;
  else if (std::none_of(free.begin(), free.end(), [&](const CachedConfiguration& c) {
             return reaches(c) && c.closure && c.closure->touches();
           }))
    ++r.no_pad_contact;
  else if (std::none_of(free.begin(), free.end(), [&](const CachedConfiguration& c) {
             return reaches(c) && c.closure && c.closure->touches() && c.contact_epsilon > 0.0 &&
                    c.contact_epsilon >= context_.min_epsilon;
           }))
    ++r.weak_at_contacts;
  else if (std::none_of(free.begin(), free.end(),
                        [](const CachedConfiguration& c) { return c.goal; }))
    ++r.closing_blocked;
}

GoalSample GraspGoalSampler::describe(const grasp::HftsNode& node,
                                      const CachedConfiguration& config, GoalKind kind) {
  GoalSample s;
  s.kind = kind;
  s.configuration = config.pregrasp;
  if (kind == GoalKind::kGoal) s.grasp = config.grasp;
  s.node = node;
  s.contacts = context_.space->representative(node);
  const grasp::GraspEvaluation e = context_.objective->evaluate(node);
  s.epsilon = e.quality;
  s.reachability = e.reachability;
  s.fingertip_error = config.fingertip_error;
  if (kind == GoalKind::kGoal) {
    s.closure = config.closure;
    s.contact_epsilon = config.contact_epsilon;
  }
  if (kind == GoalKind::kGoal) ++stats_.valid_goals;
  if (kind == GoalKind::kApproximate) ++stats_.approximate_goals;
  return s;
}

HftsGoalSampler::HftsGoalSampler(GoalSamplingContext context, HftsGoalSamplerOptions options)
    : GraspGoalSampler(context), options_(options), cache_(*context.space, options.weights) {
  // Field names as in a plan request: these options are its parameters.
  if (options.samples < 1) throw InvalidArgument("parameters.kappa", "must be >= 1");
  if (options.min_iterations < 0) throw InvalidArgument("parameters.i_min", "must be >= 0");
  if (options.max_iterations < options.min_iterations)
    throw InvalidArgument(
        "parameters.i_min",
        "must be <= i_max, got i_min = " + std::to_string(options.min_iterations) +
            " > i_max = " + std::to_string(options.max_iterations));
}

GoalSample HftsGoalSampler::sample(const FreeSpaceDistances& planner,
                                   const std::function<bool()>& stop) {
  ++stats_.calls;
  const WithApproximateGoals knowledge(planner, approximate_, context_.checker->metric());
  cache_.invalidateRatings();  // the trees have grown since the last call
  std::mt19937_64& rng = *context_.rng;
  Algorithm2Steps steps;
  steps.null_space = [this](int node) { return sampleNullSpace(node); };
  steps.new_child = [&](int parent) {
    return sampleNewChild(parent, iterationsFor(parent, knowledge));
  };
  steps.approximate = [this](int node) {
    approximate_.push_back(cache_.node(node).configurations.front().pregrasp);
    approximateNodes_.push_back(cache_.node(node).hfts);
  };
  const HandedOut found = descendForGoal(cache_, knowledge, rng, options_.samples, stop, steps);
  if (found.goal != nullptr)
    return describe(cache_.node(found.node).hfts, *found.goal, GoalKind::kGoal);
  if (approximate_.empty()) return {};  // lines 28-32
  const std::size_t pick =
      std::uniform_int_distribution<std::size_t>(0, approximate_.size() - 1)(rng);
  CachedConfiguration config;
  config.pregrasp = approximate_[pick];
  const grasp::HftsNode node = approximateNodes_[pick];
  approximate_.erase(approximate_.begin() + static_cast<std::ptrdiff_t>(pick));
  approximateNodes_.erase(approximateNodes_.begin() + static_cast<std::ptrdiff_t>(pick));
  return describe(node, config, GoalKind::kApproximate);
}

int HftsGoalSampler::iterationsFor(int parent, const FreeSpaceDistances& knowledge) {
  // Alg. 2 line 16: more effort for promising parents.
  const RatingWeights& w = cache_.weights();
  const double share = cache_.branchRating(parent, knowledge) / (w.w_f + w.w_c);
  return options_.min_iterations +
         static_cast<int>(std::lround(share * (options_.max_iterations - options_.min_iterations)));
}

int HftsGoalSampler::sampleNewChild(int parent, int iterations) {
  const CacheNode& p = cache_.node(parent);
  const grasp::ClimbResult best =
      grasp::hillClimb(*context_.objective, p.hfts, iterations, *context_.rng, &p.sampled);
  if (!best.found) return GoalHierarchyCache::kNone;
  ++stats_.nodes_explored;
  const double epsilon = best.evaluation.quality;
  bool otherHands = false;
  const int child = cache_.addChild(parent, best.best,
                                    configurationsOf(best.best, epsilon, &otherHands), epsilon);
  cache_.node(child).other_hands_sampled = otherHands;
  return child;
}

const CachedConfiguration* HftsGoalSampler::sampleNullSpace(int node) {
  if (node == GoalHierarchyCache::kNone) return nullptr;
  CacheNode& n = cache_.node(node);
  // Alg. 2 line 9: only a grasp that has a goal configuration.
  const auto isGoal = [](const CachedConfiguration& c) { return c.goal; };
  if (std::none_of(n.configurations.begin(), n.configurations.end(), isGoal)) return nullptr;
  // The KR5 is not redundant and three contacts fix the palm for a hand
  // posture, so the null space of a grasp is its other IK branches, and
  // once those are handed out, its other hand postures.
  for (int round = 0; round < 2; ++round) {
    for (CachedConfiguration& c : n.configurations) {
      if (!c.goal || c.returned) continue;
      c.returned = true;
      return &c;
    }
    if (n.other_hands_sampled) break;
    n.other_hands_sampled = true;
    for (CachedConfiguration& c : otherHandConfigurationsOf(n.hfts, n.quality))
      n.configurations.push_back(std::move(c));
    cache_.invalidateRatings();  // C_n grew
  }
  return nullptr;
}

DecoupledGoalSampler::DecoupledGoalSampler(GoalSamplingContext context, int iterations)
    : GraspGoalSampler(context), iterations_(iterations) {
  if (iterations < 1) throw InvalidArgument("parameters.iterations", "must be >= 1");
}

GoalSample DecoupledGoalSampler::sample(const FreeSpaceDistances& /*knowledge*/,
                                        const std::function<bool()>& stop) {
  ++stats_.calls;
  const grasp::HftsSpace& space = *context_.space;
  grasp::HftsNode node = space.root();
  grasp::ClimbResult climb;
  while (!space.isLeaf(node)) {  // Sec. II-A: a restart from the root
    if (stop()) return {};
    climb = grasp::hillClimb(*context_.objective, node, iterations_, *context_.rng);
    node = climb.best;
    if (explored_.insert(node).second)
      ++stats_.nodes_explored;
    else if (space.isLeaf(node))
      return {};  // this leaf was tried before
  }
  if (!(climb.evaluation.quality > 0.0)) {
    ++stats_.rejected.unstable;  // not worth Phi(h)
    return {};
  }
  if (stop()) return {};
  for (const CachedConfiguration& c : configurationsOf(node, climb.evaluation.quality))
    if (c.goal) return describe(node, c, GoalKind::kGoal);
  return {};
}

}  // namespace hfts::planner
