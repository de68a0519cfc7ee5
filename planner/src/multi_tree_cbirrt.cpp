#include "planner/multi_tree_cbirrt.h"

#include <ompl/base/PlannerData.h>
#include <ompl/geometric/PathGeometric.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "planner/path_smoothing.h"
#include "scan_nearest_neighbors.h"

namespace hfts::planner {

namespace ob = ompl::base;
namespace og = ompl::geometric;

GraspGoal::GraspGoal(const ob::SpaceInformationPtr& si, GoalSampler& sampler)
    : ob::Goal(si), sampler_(sampler) {}

bool GraspGoal::isSatisfied(const ob::State* /*state*/) const {
  return false;
}

struct MultiTreeCBiRRT::Motion {
  /// The configuration, in the planner's arena (or the caller's vector for
  /// a search probe): no allocation of its own, so that freeing 100,000
  /// nodes at the end of a plan is cheap.
  Eigen::Map<const Eigen::VectorXd> q{nullptr, 0};
  /// The same configuration as an OMPL state, made on first need
  /// (getPlannerData): most nodes never need one.
  mutable ob::State* state = nullptr;
  Motion* parent = nullptr;
  int tree = 0;

  Motion() = default;
  /// A probe for nearest-neighbour searches; `at` must outlive it.
  explicit Motion(const Eigen::VectorXd& at) : q(at.data(), at.size()) {}
};

struct MultiTreeCBiRRT::Tree {
  TreeKind kind = TreeKind::kForward;
  std::vector<Motion*> motions;
  std::unique_ptr<ScanNearestNeighbors<Motion*>> nn;
  GoalSample root;  // what the goal sampler returned (backward trees)
};

/// Omega and Gamma for the goal sampler, from the live trees.
class MultiTreeCBiRRT::Knowledge : public FreeSpaceDistances {
 public:
  explicit Knowledge(const MultiTreeCBiRRT& planner) : planner_(planner) {}
  double toNonConnected(const Eigen::VectorXd& q) const override {
    return planner_.nonConnected_->nearestDistance(q.data());
  }
  double toConnected(const Eigen::VectorXd& q) const override {
    return planner_.trees_.front()->nn->nearestDistance(q.data());
  }
  /// Between removals both sets only grow, so the nearest distance is the
  /// remembered one or that of a node added since: the same value as a
  /// full search. The goal sampler asks for hundreds of configurations per
  /// call; searches of the whole sets took a fifth of the planning time in
  /// the shelf, scanning the new nodes takes a few percent.
  FreeSpaceDistance distances(const Eigen::VectorXd& q, FreeSpaceMemo& memo) const override {
    const MultiTreeCBiRRT& p = planner_;
    const ScanNearestNeighbors<Motion*>& connected = *p.trees_.front()->nn;
    if (memo.generation != p.generation_) {
      memo.known = {toNonConnected(q), toConnected(q)};
      memo.generation = p.generation_;
      memo.non_connected_seen = p.nonConnected_->size();
      memo.connected_seen = connected.size();
      return memo.known;
    }
    memo.known.to_non_connected =
        std::min(memo.known.to_non_connected,
                 p.nonConnected_->nearestDistance(q.data(), memo.non_connected_seen));
    memo.known.to_connected =
        std::min(memo.known.to_connected, connected.nearestDistance(q.data(), memo.connected_seen));
    memo.non_connected_seen = p.nonConnected_->size();
    memo.connected_seen = connected.size();
    return memo.known;
  }

 private:
  const MultiTreeCBiRRT& planner_;
};

MultiTreeCBiRRT::MultiTreeCBiRRT(const ob::SpaceInformationPtr& si)
    : ob::Planner(si, "MultiTreeCBiRRT"), space_(weightedSpace(si)) {
  validator_ = std::dynamic_pointer_cast<CollisionMotionValidator>(si->getMotionValidator());
  if (!validator_) throw std::invalid_argument("MultiTreeCBiRRT needs a CollisionMotionValidator");
  const auto& bounds = space_.getBounds();
  lower_ = Eigen::Map<const Eigen::VectorXd>(bounds.low.data(),
                                             static_cast<Eigen::Index>(bounds.low.size()));
  upper_ = Eigen::Map<const Eigen::VectorXd>(bounds.high.data(),
                                             static_cast<Eigen::Index>(bounds.high.size()));
  specs_.directed = true;
  specs_.multithreaded = false;
  declareParameters();
}

MultiTreeCBiRRT::~MultiTreeCBiRRT() {
  clear();
}

void MultiTreeCBiRRT::declareParameters() {
  // OMPL's by-name access to this planner's settings, each with the range
  // of the planner's one table (plan_settings.h).
  ob::ParamSet& p = params();
  const auto field = [&p](const char* name, double& value) {
    declareParameter(p, name, settingRange(name), value);
  };
  field("step_size", range_);
  field("p_max", pMax_);
  field("p_min", pMin_);
  field("p_w", pW_);
  field("p_goal_tree", pGoalTree_);
  field("p_local", pLocal_);
  field("local_radius", localRadius_);
  declareParameter<double>(
      p, "d_m", settingRange("d_m"), [this](double d) { setProjectionDistance(d); },
      [this] { return dM_; });
  declareParameter(p, "smoothing_steps", settingRange("smoothing_steps"), smoothing_.steps);
  field("final_resolution", smoothing_.final_check.resolution);
  declareParameter<double>(
      p, "collision_resolution", settingRange("collision_resolution"),
      [this](double r) { validator_->setResolution(r); },
      [this] { return validator_->resolution(); });
  declareParameter<double>(
      p, "weight_arm", settingRange("weight_arm"), [this](double w) { setGroupWeight(true, w); },
      [this] { return space_.weights()(0); });
  declareParameter<double>(
      p, "weight_hand", settingRange("weight_hand"), [this](double w) { setGroupWeight(false, w); },
      [this] { return space_.weights()(space_.weights().size() - 1); });
}

void MultiTreeCBiRRT::applySettings(const PlanSettings& s) {
  range_ = s.paper.step_size;
  pMax_ = s.paper.p_max;
  pMin_ = s.paper.p_min;
  pW_ = s.paper.p_w;
  pGoalTree_ = s.paper.p_goal_tree;
  setProjectionDistance(s.paper.d_m);
  if (s.paper.weight_arm) setGroupWeight(true, *s.paper.weight_arm);
  if (s.paper.weight_hand) setGroupWeight(false, *s.paper.weight_hand);
  pLocal_ = s.heuristics.p_local;
  localRadius_ = s.heuristics.local_radius;
  validator_->setResolution(s.execution.collision_resolution);
  smoothing_.steps = static_cast<unsigned>(s.execution.smoothing_steps);
  smoothing_.final_check.resolution = s.execution.final_resolution;
  smoothing_.final_check.clearance = s.path.clearance;
}

void MultiTreeCBiRRT::setProjectionDistance(double d) {
  dM_ = d;
  if (projection_) projection_->setMaxDistance(d);
}

void MultiTreeCBiRRT::setGroupWeight(bool arm, double weight) {
  Eigen::VectorXd weights = space_.weights();
  const int armDofs = space_.armDofs();
  if (arm)
    weights.head(armDofs).setConstant(weight);
  else
    weights.tail(weights.size() - armDofs).setConstant(weight);
  // One metric for trees, motion checks and goal-sampler ratings.
  space_.setWeights(weights);
}

void MultiTreeCBiRRT::setProjection(std::shared_ptr<BackwardProjection> projection) {
  projection_ = std::move(projection);
  if (projection_) projection_->setMaxDistance(dM_);
}

void MultiTreeCBiRRT::clear() {
  ob::Planner::clear();
  for (Motion& m : motions_)
    if (m.state != nullptr) si_->freeState(m.state);
  motions_.clear();
  configurations_.clear();
  trees_.clear();
  nonConnected_.reset();
  ++generation_;
  solution_.clear();
  reached_ = {};
  stats_ = {};
  direction_ = Direction::kForward;
}

double MultiTreeCBiRRT::distance(const Eigen::Ref<const Eigen::VectorXd>& a,
                                 const Eigen::Ref<const Eigen::VectorXd>& b) const {
  return space_.distance(a, b);
}

const double* MultiTreeCBiRRT::ConfigurationArena::store(const Eigen::VectorXd& q) {
  const auto size = static_cast<std::size_t>(q.size());
  if (chunks_.empty() || used_ + size > capacity_) {
    // Chunks double from a small one (most motion plans keep a few hundred
    // nodes) and are not zeroed: zeroing a 512 kB chunk took 2 % of a
    // MotionBenchMaker plan.
    capacity_ =
        std::max(chunks_.empty() ? kFirstChunkValues : std::min(2 * capacity_, kChunkValues), size);
    chunks_.push_back(std::unique_ptr<double[]>(new double[capacity_]));
    used_ = 0;
  }
  double* at = chunks_.back().get() + used_;
  std::copy(q.data(), q.data() + size, at);
  used_ += size;
  return at;
}

void MultiTreeCBiRRT::ConfigurationArena::clear() {
  chunks_.clear();
  used_ = capacity_ = 0;
}

MultiTreeCBiRRT::Motion* MultiTreeCBiRRT::addMotion(int treeIndex, const Eigen::VectorXd& q,
                                                    Motion* parent) {
  Tree& tree = *trees_[static_cast<std::size_t>(treeIndex)];
  Motion& m = motions_.emplace_back();
  new (&m.q) Eigen::Map<const Eigen::VectorXd>(configurations_.store(q), q.size());
  m.parent = parent;
  m.tree = treeIndex;
  tree.motions.push_back(&m);
  tree.nn->add(&m);
  if (tree.kind != TreeKind::kForward) nonConnected_->add(&m);
  return &m;
}

std::unique_ptr<ScanNearestNeighbors<MultiTreeCBiRRT::Motion*>>
MultiTreeCBiRRT::makeNearestNeighbors() const {
  return std::make_unique<ScanNearestNeighbors<Motion*>>(space_.metric());
}

int MultiTreeCBiRRT::addTree(TreeKind kind, const Eigen::VectorXd& root) {
  auto tree = std::make_unique<Tree>();
  tree->kind = kind;
  tree->nn = makeNearestNeighbors();
  trees_.push_back(std::move(tree));
  const int index = static_cast<int>(trees_.size()) - 1;
  addMotion(index, root, nullptr);
  return index;
}

Eigen::VectorXd MultiTreeCBiRRT::sampleUniform() {
  Eigen::VectorXd q(lower_.size());
  for (Eigen::Index i = 0; i < q.size(); ++i)
    q(i) = std::uniform_real_distribution<double>(lower_(i), upper_(i))(rng_);
  return q;
}

Eigen::VectorXd MultiTreeCBiRRT::sampleNear(const Tree& tree) {
  const Motion* at =
      tree.motions[std::uniform_int_distribution<std::size_t>(0, tree.motions.size() - 1)(rng_)];
  Eigen::VectorXd q(at->q.size());
  std::uniform_real_distribution<double> offset(-localRadius_, localRadius_);
  for (Eigen::Index i = 0; i < q.size(); ++i)
    q(i) = std::clamp(at->q(i) + offset(rng_), lower_(i), upper_(i));
  return q;
}

void MultiTreeCBiRRT::sampleGoal(GoalSampler& sampler, const ob::PlannerTerminationCondition& ptc) {
  // Algorithm 1 lines 10-14.
  const Knowledge knowledge(*this);
  const GoalSample sample = sampler.sample(knowledge, [&ptc] { return ptc(); });
  if (sample.kind == GoalKind::kNone) return;
  const bool goal = sample.kind == GoalKind::kGoal;
  const int tree = addTree(goal ? TreeKind::kGoal : TreeKind::kApproximate, sample.configuration);
  trees_[static_cast<std::size_t>(tree)]->root = sample;
  ++(goal ? stats_.goal_trees : stats_.approximate_trees);
}

int MultiTreeCBiRRT::pickBackwardTree() {
  std::vector<int> goals, approximate;
  for (std::size_t t = 1; t < trees_.size(); ++t) {
    if (!trees_[t]) continue;
    (trees_[t]->kind == TreeKind::kGoal ? goals : approximate).push_back(static_cast<int>(t));
  }
  if (goals.empty() && approximate.empty()) return -1;
  const bool useGoals =
      approximate.empty() ||
      (!goals.empty() && std::uniform_real_distribution<double>(0.0, 1.0)(rng_) < pGoalTree_);
  const std::vector<int>& from = useGoals ? goals : approximate;
  return from[std::uniform_int_distribution<std::size_t>(0, from.size() - 1)(rng_)];
}

MultiTreeCBiRRT::GrowState MultiTreeCBiRRT::constrainedExtend(
    Tree& tree, const Eigen::VectorXd& target, const ob::PlannerTerminationCondition& ptc,
    Motion*& last) {
  Motion probe(target);
  Motion* current = tree.nn->nearest(&probe);
  last = current;
  const bool backward = tree.kind != TreeKind::kForward;
  GrowState state = GrowState::kTrapped;
  // The line's vertices live in lineScratch_ (sized once: no allocation
  // per step).
  std::array<Eigen::VectorXd, kLookahead + 1>& line = lineScratch_;
  std::array<const Eigen::VectorXd*, kLookahead + 1> vertices;
  for (std::size_t k = 0; k <= kLookahead; ++k) vertices[k] = &line[k];
  while (!ptc()) {
    // Up to kLookahead straight steps towards the target, checked in one
    // stream (the collision checker tests their states a batch at a time);
    // the same steps, nodes and answers as one step after another.
    line[0] = current->q;
    std::size_t steps = 0;
    bool reached = false, nearTarget = false;
    while (steps < kLookahead) {
      const Eigen::VectorXd& from = line[steps];
      const double d = distance(from, target);
      if (d < 1e-9) {
        reached = true;
        break;
      }
      if (backward && projection_ && projection_->nearTarget(from)) {
        nearTarget = true;
        break;
      }
      if (d <= range_)
        line[steps + 1] = target;
      else
        line[steps + 1] = from + (target - from) * (range_ / d);
      ++steps;
    }
    const std::size_t valid = steps > 0 ? validator_->validSteps(vertices.data(), steps + 1) : 0;
    for (std::size_t k = 1; k <= valid; ++k) {
      current = addMotion(current->tree, line[k], current);
      last = current;
      state = GrowState::kAdvanced;
    }
    if (valid < steps) return state;
    if (reached) return GrowState::kReached;
    if (nearTarget && !projectedStep(target, current, last, state)) return state;
  }
  return state;
}

bool MultiTreeCBiRRT::projectedStep(const Eigen::VectorXd& target, Motion*& current, Motion*& last,
                                    GrowState& state) {
  const Eigen::VectorXd from = current->q;
  const double d = distance(from, target);
  Eigen::VectorXd next = d <= range_ ? target : from + (target - from) * (range_ / d);
  if (!validator_->isValid(next)) {
    next = projection_->project(from, next);
    // The projected step may leave the joint limits: clamp it back.
    next = next.cwiseMax(lower_).cwiseMin(upper_);
    ++stats_.projections;
    // CBiRRT: stop when the projected step no longer approaches the target.
    if (distance(next, target) >= d) return false;
  }
  if (!validator_->checkMotion(from, next, validator_->resolution())) return false;
  current = addMotion(current->tree, next, current);
  last = current;
  state = GrowState::kAdvanced;
  return true;
}

int MultiTreeCBiRRT::extendTrees(const ob::PlannerTerminationCondition& ptc, Motion*& forwardEnd,
                                 Motion*& backwardEnd) {
  // Sec. III-A.1: forward extends T_f, then connects the nearest backward
  // tree to the new node; backward extends a random backward tree, then
  // connects T_f to it. The directions alternate.
  const Eigen::VectorXd random = sampleUniform();
  Tree& forward = *trees_.front();
  const int picked = direction_ == Direction::kBackward ? pickBackwardTree() : -1;
  const bool forwardFirst = picked < 0;
  direction_ = direction_ == Direction::kForward ? Direction::kBackward : Direction::kForward;
  Motion* grown = nullptr;
  if (forwardFirst) {
    if (constrainedExtend(forward, random, ptc, grown) == GrowState::kTrapped) return -1;
    if (nonConnected_->size() == 0) return -1;
    Tree& backward = *trees_[static_cast<std::size_t>(nonConnected_->nearest(grown)->tree)];
    Motion* reached = nullptr;
    if (constrainedExtend(backward, grown->q, ptc, reached) != GrowState::kReached) return -1;
    forwardEnd = grown;
    backwardEnd = reached;
    return reached->tree;
  }
  Tree& backward = *trees_[static_cast<std::size_t>(picked)];
  // Backward trees stand in narrow places (between the boards of a shelf),
  // where a step towards a far uniform sample collides at once.
  const bool local =
      pLocal_ > 0.0 && std::uniform_real_distribution<double>(0.0, 1.0)(rng_) < pLocal_;
  const Eigen::VectorXd target = local ? sampleNear(backward) : random;
  if (constrainedExtend(backward, target, ptc, grown) == GrowState::kTrapped) return -1;
  Motion* reached = nullptr;
  if (constrainedExtend(forward, grown->q, ptc, reached) != GrowState::kReached) return -1;
  forwardEnd = reached;
  backwardEnd = grown;
  return grown->tree;
}

void MultiTreeCBiRRT::dropTree(int index) {
  trees_[static_cast<std::size_t>(index)].reset();
  ++generation_;
  // One rebuild from the live trees: GNAT rebuilds itself every few
  // removals, so removing a big tree node by node took seconds.
  std::vector<Motion*> remaining;
  for (std::size_t t = 1; t < trees_.size(); ++t)
    if (trees_[t])
      remaining.insert(remaining.end(), trees_[t]->motions.begin(), trees_[t]->motions.end());
  nonConnected_->clear();
  nonConnected_->add(remaining);
}

void MultiTreeCBiRRT::mergeIntoForward(int index, Motion* forwardEnd, Motion* backwardEnd) {
  // Algorithm 1 line 18: reverse the parent chain from the meeting node to
  // the backward root, hang it below the forward node it met; every node of
  // the tree becomes connected free space.
  Motion* previous = forwardEnd;
  for (Motion* m = backwardEnd; m != nullptr;) {
    Motion* next = m->parent;
    m->parent = previous;
    previous = m;
    m = next;
  }
  Tree& forward = *trees_.front();
  std::vector<Motion*> moved = trees_[static_cast<std::size_t>(index)]->motions;
  dropTree(index);
  for (Motion* m : moved) {
    m->tree = 0;
    forward.motions.push_back(m);
    forward.nn->add(m);
  }
  ++stats_.merged_trees;
}

ob::PlannerStatus MultiTreeCBiRRT::solve(const ob::PlannerTerminationCondition& ptc) {
  checkValidity();
  auto* goal = dynamic_cast<GraspGoal*>(pdef_->getGoal().get());
  if (goal == nullptr)
    throw std::invalid_argument("MultiTreeCBiRRT solves GraspGoal problems only");
  const ob::State* start = pis_.nextStart();
  if (start == nullptr) return ob::PlannerStatus::INVALID_START;
  clear();
  rng_.seed(seed_);
  nonConnected_ = makeNearestNeighbors();
  addTree(TreeKind::kForward, space_.toVector(start));
  GoalSampler& sampler = goal->sampler();
  ob::PlannerStatus status = ob::PlannerStatus::TIMEOUT;
  while (!ptc()) {  // Algorithm 1 line 6
    ++stats_.iterations;
    const double live = static_cast<double>(std::count_if(
        trees_.begin() + 1, trees_.end(), [](const auto& t) { return t != nullptr; }));
    const double pGoal = pMax_ * std::exp(-pW_ * live) + pMin_;  // line 8
    if (std::uniform_real_distribution<double>(0.0, 1.0)(rng_) <= pGoal) {
      sampleGoal(sampler, ptc);
      continue;
    }
    Motion* forwardEnd = nullptr;
    Motion* backwardEnd = nullptr;
    const int connected = extendTrees(ptc, forwardEnd, backwardEnd);
    if (connected < 0) continue;
    if (trees_[static_cast<std::size_t>(connected)]->kind == TreeKind::kApproximate) {
      mergeIntoForward(connected, forwardEnd, backwardEnd);  // lines 21-22
    } else if (extractAndShortcutPath(connected, forwardEnd, backwardEnd, ptc)) {
      status = ob::PlannerStatus::EXACT_SOLUTION;  // line 20
      break;
    }
  }
  stats_.forward_tree_size = trees_.front()->motions.size();
  stats_.backward_tree_nodes = nonConnected_->size();
  return status;
}

bool MultiTreeCBiRRT::extractAndShortcutPath(int index, Motion* forwardEnd, Motion* backwardEnd,
                                             const ob::PlannerTerminationCondition& ptc) {
  std::vector<Eigen::VectorXd> path;
  for (Motion* m = forwardEnd; m != nullptr; m = m->parent) path.push_back(m->q);
  std::reverse(path.begin(), path.end());
  // backwardEnd repeats forwardEnd's configuration; continue from its parent.
  for (Motion* m = backwardEnd->parent; m != nullptr; m = m->parent) path.push_back(m->q);
  PathSmoothing smoothing = smoothing_;
  smoothing.seed = static_cast<std::uint32_t>(rng_());
  // The goal's own check first (a grasp simulated in physics fails far
  // more often than a path its final check): a proof of a path to a goal
  // that is dropped anyway would be wasted.
  if (goalCheck_ && !goalCheck_(trees_[static_cast<std::size_t>(index)]->root)) {
    ++stats_.dropped_goals;
    dropTree(index);
    return false;
  }
  // Smoothed and through the final check: a path that fails it is never
  // returned (path_smoothing.h).
  PathCheckReport report;
  const auto smoothingBegan = std::chrono::steady_clock::now();
  std::optional<std::vector<Eigen::VectorXd>> checked =
      smoothAndRecheck(si_, path, smoothing, ptc, &report);
  stats_.smoothing_time +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - smoothingBegan).count();
  stats_.final_check_time += report.seconds;
  stats_.certificate_queries += report.queries;
  if (!checked) {
    ++stats_.rejected_paths;
    // The goal itself may still be reached by another path.
    static_cast<GraspGoal&>(*pdef_->getGoal())
        .sampler()
        .pathRejected(trees_[static_cast<std::size_t>(index)]->root);
    dropTree(index);
    return false;
  }
  stats_.path_length_raw = pathLength(space_, path);
  stats_.path_length_smoothed = pathLength(space_, *checked);
  solution_ = std::move(*checked);
  pathCheck_ = report;
  reached_ = trees_[static_cast<std::size_t>(index)]->root;
  auto geometric = std::make_shared<og::PathGeometric>(si_);
  for (const Eigen::VectorXd& q : solution_) {
    ob::State* state = si_->allocState();
    space_.fromVector(q, state);
    geometric->append(state);
    si_->freeState(state);
  }
  pdef_->addSolutionPath(geometric, false, 0.0, getName());
  return true;
}

void MultiTreeCBiRRT::getPlannerData(ob::PlannerData& data) const {
  ob::Planner::getPlannerData(data);
  const auto stateOf = [this](const Motion* m) {
    if (m->state == nullptr) {
      m->state = si_->allocState();
      space_.fromVector(m->q, m->state);
    }
    return m->state;
  };
  for (const auto& tree : trees_) {
    if (!tree) continue;
    for (const Motion* m : tree->motions) {
      const unsigned tag = static_cast<unsigned>(m->tree);
      if (m->parent == nullptr) {
        if (m->tree == 0)
          data.addStartVertex(ob::PlannerDataVertex(stateOf(m), static_cast<int>(tag)));
        else
          data.addGoalVertex(ob::PlannerDataVertex(stateOf(m), static_cast<int>(tag)));
      } else {
        data.addEdge(ob::PlannerDataVertex(stateOf(m->parent), static_cast<int>(tag)),
                     ob::PlannerDataVertex(stateOf(m), static_cast<int>(tag)));
      }
    }
  }
}

}  // namespace hfts::planner
