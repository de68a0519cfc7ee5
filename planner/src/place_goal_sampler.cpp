#include "place_goal_sampler.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "robot/kinematics.h"
#include "with_approximate_goals.h"

namespace hfts::planner {

namespace {

/// Yaw sectors of level 1 (a quarter turn each); each level halves them.
constexpr int kFirstYawSectors = 4;
/// The deepest hierarchy, whatever the region's size.
constexpr int kMaxLevels = 8;
/// Children of a node below level 1: two halves in x, y and yaw.
constexpr std::uint64_t kChildren = 8;
/// Room to the region's edges that counts fully in the objective (m).
constexpr double kFullRoom = 0.05;
/// Uncached children a SAMPLENEWCHILD rates before it settles.
constexpr int kClimbDraws = 4;

/// Where a contact polygon's corners are, in the region's frame.
Eigen::Matrix3Xd cornersOnTop(const PlaceRegion& region, const grasp::RestingFace& face,
                              const Eigen::Isometry3d& pose) {
  return (region.frame.inverse() * pose) * face.polygon;
}

}  // namespace

// --- the hierarchy ----------------------------------------------------------

PlaceHierarchy::PlaceHierarchy(const PlaceRegion& region, int faces, double leafCell)
    : region_(region), faces_(faces) {
  low_ = -region.half_extents;
  high_ = region.half_extents;
  if (region.area) {
    // The area's corners in the region's frame, clipped to the top.
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e9), hi = Eigen::Vector2d::Constant(-1e9);
    for (const Eigen::Vector2d& c :
         {region.area->min(), region.area->max(),
          Eigen::Vector2d(region.area->min().x(), region.area->max().y()),
          Eigen::Vector2d(region.area->max().x(), region.area->min().y())}) {
      const Eigen::Vector3d local =
          region.frame.inverse() * Eigen::Vector3d(c.x(), c.y(), region.frame.translation().z());
      lo = lo.cwiseMin(local.head<2>());
      hi = hi.cwiseMax(local.head<2>());
    }
    low_ = low_.cwiseMax(lo);
    high_ = high_.cwiseMin(hi);
  }
  const double extent = (high_ - low_).maxCoeff();
  levels_ = 2;
  while (levels_ < kMaxLevels && extent / std::ldexp(1.0, levels_) > leafCell) ++levels_;
}

std::uint64_t PlaceHierarchy::numChildren(const grasp::HftsNode& node) const {
  if (node.level == 0) return static_cast<std::uint64_t>(faces_) * 4 * kFirstYawSectors;
  return node.level < levels_ ? kChildren : 0;
}

double PlaceHierarchy::numLeaves(const grasp::HftsNode& node) const {
  const double below = std::pow(static_cast<double>(kChildren), levels_ - std::max(node.level, 1));
  return node.level == 0 ? static_cast<double>(numChildren(node)) * below : below;
}

grasp::HftsNode PlaceHierarchy::child(const grasp::HftsNode& parent, std::uint64_t index) const {
  grasp::HftsNode c;
  c.level = parent.level + 1;
  const auto bit = [&](int b) { return static_cast<std::uint32_t>((index >> b) & 1U); };
  if (parent.level == 0) {
    c.parts[0] = static_cast<std::uint32_t>(index / (4 * kFirstYawSectors));
    const auto rest = static_cast<std::uint32_t>(index % (4 * kFirstYawSectors));
    c.parts[1] = rest & 1U;
    c.parts[2] = (rest >> 1) & 1U;
    c.parts[3] = rest >> 2;
    return c;
  }
  c.parts[0] = parent.parts[0];
  c.parts[1] = 2 * parent.parts[1] + bit(0);
  c.parts[2] = 2 * parent.parts[2] + bit(1);
  c.parts[3] = 2 * parent.parts[3] + bit(2);
  return c;
}

Eigen::Vector2d PlaceHierarchy::cellCentre(const grasp::HftsNode& node) const {
  const double cells = std::ldexp(1.0, node.level);
  const Eigen::Vector2d local =
      low_ + Eigen::Vector2d((node.parts[1] + 0.5) / cells, (node.parts[2] + 0.5) / cells)
                 .cwiseProduct(high_ - low_);
  return (region_.frame * Eigen::Vector3d(local.x(), local.y(), 0.0)).head<2>();
}

double PlaceHierarchy::yaw(const grasp::HftsNode& node) const {
  const double sectors = kFirstYawSectors * std::ldexp(1.0, node.level - 1);
  return -M_PI + 2.0 * M_PI * (node.parts[3] + 0.5) / sectors;
}

// --- what both samplers share ----------------------------------------------

PlacementSampler::PlacementSampler(PlaceSamplingContext context) : context_(std::move(context)) {
  if (context_.region == nullptr || context_.faces == nullptr || context_.faces->empty() ||
      context_.ik == nullptr || context_.checker == nullptr || context_.rng == nullptr ||
      !context_.finish)
    throw std::invalid_argument("placement sampler: incomplete context");
}

const Placement* PlacementSampler::placementOf(const Eigen::VectorXd& q) const {
  for (const Placement& p : goals_)
    if (!p.descent.empty() && p.descent.front().isApprox(q, 1e-12)) return &p;
  return nullptr;
}

Eigen::Isometry3d PlacementSampler::placement(int face, const Eigen::Vector2d& xy,
                                              double yaw) const {
  return grasp::restingPose((*context_.faces)[static_cast<std::size_t>(face)],
                            context_.center_of_mass, xy, yaw,
                            context_.region->frame.translation().z() + robot::kRestingClearance);
}

std::vector<Eigen::VectorXd> PlacementSampler::prePlaces(const Eigen::Isometry3d& pose,
                                                         bool count) {
  Eigen::Isometry3d palm = pose * context_.object_in_palm.inverse();
  palm.translation().z() += context_.height;
  const robot::RobotModel& robot = context_.checker->model();
  const Eigen::Index n = robot.numArmDofs();
  std::vector<Eigen::VectorXd> arms =
      context_.ik->solvePalm(context_.robot_base.inverse() * palm, *context_.rng);
  arms = robot::nearestWholeTurns(arms, context_.start.head(n), robot.lowerLimits().head(n),
                                  robot.upperLimits().head(n));
  if (arms.empty() && count) ++rejected_.no_arm_ik;
  std::vector<Eigen::VectorXd> free;
  for (const Eigen::VectorXd& arm : arms) {
    Eigen::VectorXd q = context_.start;
    q.head(n) = arm;
    if (!context_.checker->inCollision(q)) free.push_back(std::move(q));
  }
  if (!arms.empty() && free.empty() && count) ++rejected_.colliding;
  return free;
}

bool PlacementSampler::handFits(const Eigen::Isometry3d& pose) const {
  const robot::RobotModel& robot = context_.checker->model();
  return !context_.checker->handInCollision(pose * context_.object_in_palm.inverse(),
                                            context_.start.tail(robot.numHandDofs()), {});
}

std::vector<CachedConfiguration> PlacementSampler::configurationsOf(int face,
                                                                    const Eigen::Isometry3d& pose,
                                                                    bool leaf) {
  const grasp::RestingFace& resting = (*context_.faces)[static_cast<std::size_t>(face)];
  const bool stands = supported(*context_.region, resting, context_.center_of_mass, pose);
  if (leaf && !stands) {
    ++rejected_.unsupported;
    return {};
  }
  // The hand where it puts the object down: a finger under the object, or
  // the palm in the support, and no descent can end there.
  if (leaf && !handFits(pose)) {
    ++rejected_.descent_blocked;
    return {};
  }
  std::vector<CachedConfiguration> out;
  for (Eigen::VectorXd& q : prePlaces(pose, leaf)) {
    CachedConfiguration c;
    c.pregrasp = std::move(q);
    c.grasp = c.pregrasp;
    c.collision_free = true;
    if (leaf) {
      if (std::optional<Placement> p = context_.finish(pose, resting, c.pregrasp, rejected_)) {
        c.goal = true;
        goals_.push_back(std::move(*p));
      }
    }
    out.push_back(std::move(c));
  }
  return out;
}

GoalSample PlacementSampler::handOut(const CachedConfiguration& goal) {
  ++stats_.valid_goals;
  GoalSample out;
  out.kind = GoalKind::kGoal;
  out.configuration = goal.pregrasp;
  out.grasp = goal.pregrasp;
  return out;
}

// --- coupled ----------------------------------------------------------------

HierarchicalPlaceSampler::HierarchicalPlaceSampler(PlaceSamplingContext context,
                                                   HftsGoalSamplerOptions options)
    : PlacementSampler(std::move(context)),
      options_(options),
      hierarchy_(*context_.region, static_cast<int>(context_.faces->size())),
      cache_(hierarchy_, options.weights) {
  for (const grasp::RestingFace& f : *context_.faces)
    stablest_ = std::max(stablest_, f.tipping_angle);
}

Eigen::Isometry3d HierarchicalPlaceSampler::placementOf(const grasp::HftsNode& node) const {
  return placement(static_cast<int>(node.parts[0]), hierarchy_.cellCentre(node),
                   hierarchy_.yaw(node));
}

double HierarchicalPlaceSampler::objective(const grasp::HftsNode& node) const {
  const grasp::RestingFace& face = (*context_.faces)[node.parts[0]];
  const Eigen::Isometry3d pose = placementOf(node);
  if (!supported(*context_.region, face, context_.center_of_mass, pose) || !handFits(pose))
    return 0.0;
  const Eigen::Matrix3Xd corners = cornersOnTop(*context_.region, face, pose);
  const Eigen::Vector2d& half = context_.region->half_extents;
  double room = kFullRoom;
  for (Eigen::Index c = 0; c < corners.cols(); ++c)
    room = std::min({room, half.x() - std::abs(corners(0, c)), half.y() - std::abs(corners(1, c))});
  const double stability = stablest_ > 0.0 ? face.tipping_angle / stablest_ : 1.0;
  return stability * (0.5 + 0.5 * std::max(room, 0.0) / kFullRoom);
}

int HierarchicalPlaceSampler::sampleNewChild(int parent) {
  const CacheNode& p = cache_.node(parent);
  const std::uint64_t children = hierarchy_.numChildren(p.hfts);
  if (p.sampled.size() >= children) return GoalHierarchyCache::kNone;
  std::uniform_int_distribution<std::uint64_t> pick(0, children - 1);
  grasp::HftsNode best;
  double bestValue = -1.0;
  // kClimbDraws uncached children (drawn with repeats: a few more tries).
  for (int draws = 0, tries = 0; draws < kClimbDraws && tries < 4 * kClimbDraws; ++tries) {
    const grasp::HftsNode c = hierarchy_.child(p.hfts, pick(*context_.rng));
    if (p.sampled.count(c) > 0) continue;
    ++draws;
    const double value = objective(c);
    if (value > bestValue) best = c, bestValue = value;
  }
  if (bestValue < 0.0) return GoalHierarchyCache::kNone;
  ++stats_.nodes_explored;
  const bool leaf = hierarchy_.isLeaf(best);
  std::vector<CachedConfiguration> configurations =
      configurationsOf(static_cast<int>(best.parts[0]), placementOf(best), leaf);
  return cache_.addChild(parent, best, std::move(configurations), bestValue);
}

GoalSample HierarchicalPlaceSampler::sample(const FreeSpaceDistances& planner,
                                            const std::function<bool()>& stop) {
  ++stats_.calls;
  const WithApproximateGoals knowledge(planner, approximate_, context_.checker->metric());
  cache_.invalidateRatings();  // the trees have grown since the last call
  std::mt19937_64& rng = *context_.rng;
  Algorithm2Steps steps;
  // Another goal of a cached leaf: its other IK branches.
  steps.null_space = [this](int node) -> const CachedConfiguration* {
    for (CachedConfiguration& c : cache_.node(node).configurations)
      if (c.goal && !c.returned) {
        c.returned = true;
        return &c;
      }
    return nullptr;
  };
  steps.new_child = [this](int parent) { return sampleNewChild(parent); };
  steps.approximate = [this](int node) {
    approximate_.push_back(cache_.node(node).configurations.front().pregrasp);
  };
  const HandedOut found = descendForGoal(cache_, knowledge, rng, options_.samples, stop, steps);
  if (found.goal != nullptr) return handOut(*found.goal);
  if (approximate_.empty()) return {};  // lines 28-32
  const std::size_t pick =
      std::uniform_int_distribution<std::size_t>(0, approximate_.size() - 1)(rng);
  GoalSample out;
  out.kind = GoalKind::kApproximate;
  out.configuration = approximate_[pick];
  approximate_.erase(approximate_.begin() + static_cast<std::ptrdiff_t>(pick));
  ++stats_.approximate_goals;
  return out;
}

// --- decoupled --------------------------------------------------------------

DecoupledPlaceSampler::DecoupledPlaceSampler(PlaceSamplingContext context)
    : PlacementSampler(std::move(context)) {}

GoalSample DecoupledPlaceSampler::sample(const FreeSpaceDistances& /*knowledge*/,
                                         const std::function<bool()>& stop) {
  ++stats_.calls;
  if (stop()) return {};
  const std::optional<Eigen::Isometry3d> pose =
      samplePlacement(*context_.region, *context_.faces, context_.center_of_mass, *context_.rng, 1);
  if (!pose) {
    ++rejected_.unsupported;
    return {};
  }
  // The face it rests on: the one whose normal the pose turns to world -z.
  int face = 0;
  double lowest = 2.0;
  for (std::size_t f = 0; f < context_.faces->size(); ++f) {
    const double z = (pose->linear() * (*context_.faces)[f].normal).z();
    if (z < lowest) lowest = z, face = static_cast<int>(f);
  }
  ++stats_.nodes_explored;
  std::vector<CachedConfiguration> configurations = configurationsOf(face, *pose, true);
  for (CachedConfiguration& c : configurations)
    if (c.goal) return handOut(c);
  return {};
}

}  // namespace hfts::planner
