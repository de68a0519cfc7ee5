#include "planner/path_smoothing.h"

#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/PathSimplifier.h>

#include <algorithm>
#include <chrono>
#include <functional>
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

/// A path found at the time limit is still re-checked, never returned
/// unchecked, but for at most kGrace after the limit: then it is dropped,
/// so a planner returns within its limit plus about kGrace. The grace runs
/// from the last poll that found the limit not passed (a smoothing batch
/// or a long segment check may straddle the limit: its overrun counts).
/// 25 ms leaves room within the promised 50 ms for the teardown (a few ms)
/// and, in the RRTConnect baseline, the sampling thread's last step.
class LimitWithGrace {
 public:
  explicit LimitWithGrace(const ob::PlannerTerminationCondition& ptc)
      : ptc_(ptc), lastBefore_(std::chrono::steady_clock::now()) {}
  /// The termination condition (polled until it fires).
  bool fired() {
    if (fired_) return true;
    if (ptc_()) return fired_ = true;
    lastBefore_ = std::chrono::steady_clock::now();
    return false;
  }
  bool expired() {
    constexpr std::chrono::milliseconds kGrace{25};
    return fired() && std::chrono::steady_clock::now() - lastBefore_ > kGrace;
  }

 private:
  const ob::PlannerTerminationCondition& ptc_;
  bool fired_ = false;
  std::chrono::steady_clock::time_point lastBefore_;
};

/// Steps of a smoothing batch, between which the termination condition is
/// polled.
constexpr unsigned kBatch = 20;

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

/// Segments found free at the final resolution, so that the paths a
/// repair compares, which share most of their segments, check each once.
class CheckedSegments {
 public:
  bool contains(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const {
    return std::any_of(free_.begin(), free_.end(),
                       [&](const auto& s) { return s.first == a && s.second == b; });
  }
  void add(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { free_.emplace_back(a, b); }

 private:
  std::vector<std::pair<Eigen::VectorXd, Eigen::VectorXd>> free_;
};

bool validWithin(const CollisionMotionValidator& validator,
                 const std::vector<Eigen::VectorXd>& path, double resolution, LimitWithGrace& limit,
                 CheckedSegments* checked = nullptr) {
  if (path.empty() || !validator.isValid(path.front())) return false;
  for (std::size_t i = 1; i < path.size(); ++i) {
    if (checked != nullptr && checked->contains(path[i - 1], path[i])) continue;
    if (limit.expired() || !validator.checkMotion(path[i - 1], path[i], resolution)) return false;
    if (checked != nullptr) checked->add(path[i - 1], path[i]);
  }
  return true;
}

/// OMPL's passes on `path`: the path after every batch of steps, the
/// first being `path` itself.
std::vector<std::vector<Eigen::VectorXd>> smoothInBatches(const ob::SpaceInformationPtr& si,
                                                          const std::vector<Eigen::VectorXd>& path,
                                                          const PathSmoothing& smoothing,
                                                          const std::function<bool()>& stop) {
  std::vector<std::vector<Eigen::VectorXd>> snapshots{path};
  if (path.size() < 3 || smoothing.steps == 0) return snapshots;
  const WeightedStateSpace& space = weightedSpace(si);
  og::PathGeometric geometric(si);
  ob::State* state = si->allocState();
  for (const Eigen::VectorXd& q : path) {
    space.fromVector(q, state);
    geometric.append(state);
  }
  si->freeState(state);
  auto keep = [&](bool shortened) {
    if (!shortened) return false;
    std::vector<Eigen::VectorXd>& out = snapshots.emplace_back();
    for (const ob::State* s : geometric.getStates()) out.push_back(space.toVector(s));
    return true;
  };
  SeededSimplifier simplifier(si, smoothing.seed);
  // A pass ends early once two batches in a row shortened nothing: later
  // batches rarely do (same lengths to 1-2 % on the bundled scenes), and
  // each of their attempts costs motion checks.
  constexpr unsigned kIdleBatches = 2;
  unsigned idle = 0;
  for (unsigned done = 0; done < smoothing.steps && (done == 0 || !stop()) && idle < kIdleBatches;
       done += kBatch)
    idle = keep(simplifier.reduceVertices(geometric, kBatch, kBatch)) ? 0 : idle + 1;
  idle = 0;
  for (unsigned done = 0; done < smoothing.steps && !stop() && idle < kIdleBatches; done += kBatch)
    idle = keep(simplifier.shortcutPath(geometric, kBatch, kBatch)) ? 0 : idle + 1;
  return snapshots;
}

}  // namespace

std::vector<Eigen::VectorXd> smoothPath(const ob::SpaceInformationPtr& si,
                                        const std::vector<Eigen::VectorXd>& path,
                                        const PathSmoothing& smoothing,
                                        const ob::PlannerTerminationCondition& ptc) {
  return smoothInBatches(si, path, smoothing, [&ptc] { return ptc(); }).back();
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
  const auto stop = [&limit] { return limit.fired(); };
  const std::vector<std::vector<Eigen::VectorXd>> snapshots =
      smoothInBatches(si, raw, smoothing, stop);
  CheckedSegments checked;
  if (validWithin(*validator, snapshots.back(), smoothing.final_resolution, limit, &checked))
    return snapshots.back();
  if (limit.fired()) return std::nullopt;
  // A shortcut free at the tree resolution grazed an obstacle between its
  // samples. Repair: find a smoothing batch whose path passes the re-check
  // and whose successor does not (bisection; the unsmoothed path must pass
  // if it comes to that), then smooth on from there for one batch of each
  // pass with every shortcut checked at the final resolution. The full
  // passes at that resolution cost 2-3 times a whole plan in the bin
  // scene, for paths 0-10 % shorter than after one batch.
  std::size_t good = 0, bad = snapshots.size() - 1;
  while (bad - good > 1) {
    const std::size_t mid = (good + bad) / 2;
    if (validWithin(*validator, snapshots[mid], smoothing.final_resolution, limit, &checked))
      good = mid;
    else
      bad = mid;
  }
  if (good == 0 &&
      !validWithin(*validator, snapshots[good], smoothing.final_resolution, limit, &checked))
    return std::nullopt;
  if (limit.expired()) return snapshots[good];
  std::vector<Eigen::VectorXd> repaired;
  {
    const ScopedResolution fine(*validator, smoothing.final_resolution);
    PathSmoothing oneBatch = smoothing;
    oneBatch.steps = std::min(smoothing.steps, kBatch);
    repaired = smoothInBatches(si, snapshots[good], oneBatch, stop).back();
  }
  if (validWithin(*validator, repaired, smoothing.final_resolution, limit, &checked))
    return repaired;
  return snapshots[good];
}

double pathLength(const WeightedStateSpace& space, const std::vector<Eigen::VectorXd>& path) {
  double length = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) length += space.distance(path[i - 1], path[i]);
  return length;
}

}  // namespace hfts::planner
