#include "planner/path_smoothing.h"

#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/PathSimplifier.h>

#include <chrono>
#include <optional>
#include <stdexcept>

namespace hfts::planner {

namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace {

/// OMPL's shortcutting with its random generator seeded from ours.
class SeededSimplifier : public og::PathSimplifier {
 public:
  SeededSimplifier(const ob::SpaceInformationPtr& si, std::uint32_t seed) : PathSimplifier(si) {
    rng_.setLocalSeed(seed);
  }
};

const WeightedStateSpace& weightedSpace(const ob::SpaceInformationPtr& si) {
  const auto* space = dynamic_cast<const WeightedStateSpace*>(si->getStateSpace().get());
  if (space == nullptr)
    throw std::invalid_argument("path smoothing needs a WeightedStateSpace (makeSpaceInformation)");
  return *space;
}

/// A path found at the time limit is still re-checked, never returned
/// unchecked, but for at most kGrace after the limit: then it is dropped,
/// so a planner returns within its limit plus about kGrace.
class LimitWithGrace {
 public:
  explicit LimitWithGrace(const ob::PlannerTerminationCondition& ptc) : ptc_(ptc) {}
  bool expired() {
    constexpr std::chrono::milliseconds kGrace{40};
    if (!ptc_()) return false;
    const auto now = std::chrono::steady_clock::now();
    if (!fired_) fired_ = now;
    return now - *fired_ > kGrace;
  }

 private:
  const ob::PlannerTerminationCondition& ptc_;
  std::optional<std::chrono::steady_clock::time_point> fired_;
};

/// Sets a motion validator's resolution for its lifetime.
class ScopedResolution {
 public:
  ScopedResolution(CollisionMotionValidator& validator, double resolution)
      : validator_(validator), previous_(validator.resolution()) {
    validator_.setResolution(resolution);
  }
  ~ScopedResolution() { validator_.setResolution(previous_); }
  ScopedResolution(const ScopedResolution&) = delete;
  ScopedResolution& operator=(const ScopedResolution&) = delete;

 private:
  CollisionMotionValidator& validator_;
  double previous_;
};

bool validWithin(const CollisionMotionValidator& validator,
                 const std::vector<Eigen::VectorXd>& path, double resolution,
                 LimitWithGrace& limit) {
  if (path.empty() || !validator.isValid(path.front())) return false;
  for (std::size_t i = 1; i < path.size(); ++i)
    if (limit.expired() || !validator.checkMotion(path[i - 1], path[i], resolution)) return false;
  return true;
}

}  // namespace

std::vector<Eigen::VectorXd> smoothPath(const ob::SpaceInformationPtr& si,
                                        const std::vector<Eigen::VectorXd>& path,
                                        const PathSmoothing& smoothing,
                                        const ob::PlannerTerminationCondition& ptc) {
  if (path.size() < 3 || smoothing.steps == 0) return path;
  const WeightedStateSpace& space = weightedSpace(si);
  og::PathGeometric geometric(si);
  ob::State* state = si->allocState();
  for (const Eigen::VectorXd& q : path) {
    space.fromVector(q, state);
    geometric.append(state);
  }
  si->freeState(state);
  SeededSimplifier simplifier(si, smoothing.seed);
  constexpr unsigned kBatch = 20;
  // A pass ends early once two batches in a row shortened nothing: later
  // batches rarely do (same lengths to 1-2 % on the bundled scenes), and
  // each of their attempts costs motion checks.
  constexpr unsigned kIdleBatches = 2;
  unsigned idle = 0;
  for (unsigned done = 0; done < smoothing.steps && (done == 0 || !ptc()) && idle < kIdleBatches;
       done += kBatch)
    idle = simplifier.reduceVertices(geometric, kBatch, kBatch) ? 0 : idle + 1;
  idle = 0;
  for (unsigned done = 0; done < smoothing.steps && !ptc() && idle < kIdleBatches; done += kBatch)
    idle = simplifier.shortcutPath(geometric, kBatch, kBatch) ? 0 : idle + 1;
  std::vector<Eigen::VectorXd> out;
  for (const ob::State* s : geometric.getStates()) out.push_back(space.toVector(s));
  return out;
}

bool denselyValid(const CollisionMotionValidator& validator,
                  const std::vector<Eigen::VectorXd>& path, double resolution) {
  const ob::PlannerTerminationCondition never = ob::plannerNonTerminatingCondition();
  LimitWithGrace limit(never);
  return validWithin(validator, path, resolution, limit);
}

std::optional<std::vector<Eigen::VectorXd>> smoothAndRecheck(
    const ob::SpaceInformationPtr& si, const std::vector<Eigen::VectorXd>& raw,
    const PathSmoothing& smoothing, const ob::PlannerTerminationCondition& ptc) {
  const auto validator =
      std::dynamic_pointer_cast<CollisionMotionValidator>(si->getMotionValidator());
  if (!validator) throw std::invalid_argument("path smoothing needs a CollisionMotionValidator");
  LimitWithGrace limit(ptc);
  limit.expired();  // starts the grace period if the limit has passed already
  std::vector<Eigen::VectorXd> smoothed = smoothPath(si, raw, smoothing, ptc);
  if (validWithin(*validator, smoothed, smoothing.final_resolution, limit)) return smoothed;
  if (ptc()) return std::nullopt;
  // A shortcut free at the tree resolution grazed an obstacle between its
  // samples. Smoothing again with every shortcut checked at the final
  // resolution costs several times as much, so only here: the shortcuts
  // are then as fine as the re-check, and only segments of `raw` left in
  // place can still fail it (then `raw` fails too).
  {
    const ScopedResolution fine(*validator, smoothing.final_resolution);
    smoothed = smoothPath(si, raw, smoothing, ptc);
  }
  if (validWithin(*validator, smoothed, smoothing.final_resolution, limit)) return smoothed;
  return std::nullopt;
}

double pathLength(const WeightedStateSpace& space, const std::vector<Eigen::VectorXd>& path) {
  double length = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) length += space.distance(path[i - 1], path[i]);
  return length;
}

}  // namespace hfts::planner
