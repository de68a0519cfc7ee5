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

/// Segments that passed the final check, with the clearance their proof
/// measured, so that the paths a repair compares, which share most of their
/// segments, check each once.
class CheckedSegments {
 public:
  const std::optional<double>* find(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const {
    for (const Segment& s : free_)
      if (s.a == a && s.b == b) return &s.clearance;
    return nullptr;
  }
  void add(const Eigen::VectorXd& a, const Eigen::VectorXd& b, std::optional<double> clearance) {
    free_.push_back({a, b, clearance});
  }

 private:
  struct Segment {
    Eigen::VectorXd a, b;
    std::optional<double> clearance;
  };
  std::vector<Segment> free_;
};

/// The final check of `path` segment by segment (the last under
/// `lastRule`), each segment once over the
/// checks that share `checked`; its time and queries added to `report`.
bool validWithin(const CollisionMotionValidator& validator,
                 const std::vector<Eigen::VectorXd>& path, const MotionCheck& check,
                 robot::CertifyRule lastRule, LimitWithGrace& limit, CheckedSegments& checked,
                 PathCheckReport& report) {
  const auto began = std::chrono::steady_clock::now();
  const auto timed = [&](bool valid) {
    report.seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
    return valid;
  };
  if (path.empty()) return timed(false);
  // A proof measures where it starts; a sampled check looks at the first
  // state here, then at each segment's others.
  if (!check.certifies() && !validator.isValid(path.front())) return timed(false);
  if (path.size() == 1 && check.certifies())
    return timed(checkMotion(validator.checker(), check, path, lastRule).free);
  for (std::size_t i = 1; i < path.size(); ++i) {
    if (checked.find(path[i - 1], path[i]) != nullptr) continue;
    if (limit.expired()) return timed(false);
    const robot::CertifyRule rule = i + 1 == path.size() ? lastRule : robot::CertifyRule::kTransit;
    const MotionVerdict verdict =
        check.certifies()
            ? checkMotion(validator.checker(), check, {path[i - 1], path[i]}, rule,
                          [&limit] { return limit.expired(); })
            : MotionVerdict{validator.checkMotion(path[i - 1], path[i], check.resolution), {}, 0};
    report.queries += verdict.queries;
    if (!verdict.free) return timed(false);
    checked.add(path[i - 1], path[i], verdict.clearance);
  }
  return timed(true);
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
  CheckedSegments checked;
  PathCheckReport report;
  MotionCheck sampled;
  sampled.resolution = resolution;
  return validWithin(validator, path, sampled, robot::CertifyRule::kTransit, limit, checked,
                     report);
}

std::optional<std::vector<Eigen::VectorXd>> smoothAndRecheck(
    const ob::SpaceInformationPtr& si, const std::vector<Eigen::VectorXd>& raw,
    const PathSmoothing& smoothing, const ob::PlannerTerminationCondition& ptc,
    PathCheckReport* report) {
  const auto validator =
      std::dynamic_pointer_cast<CollisionMotionValidator>(si->getMotionValidator());
  if (!validator) throw std::invalid_argument("path smoothing needs a CollisionMotionValidator");
  LimitWithGrace limit(ptc);
  const auto stop = [&limit] { return limit.fired(); };
  const std::vector<std::vector<Eigen::VectorXd>> snapshots =
      smoothInBatches(si, raw, smoothing, stop);
  const MotionCheck& check = smoothing.final_check;
  CheckedSegments checked;
  PathCheckReport own;
  PathCheckReport& found = report != nullptr ? *report : own;
  found = {};
  const auto passes = [&](const std::vector<Eigen::VectorXd>& path) {
    return validWithin(*validator, path, check, smoothing.last_rule, limit, checked, found);
  };
  // The returned path's smallest clearance, from its segments' proofs.
  const auto returned = [&](const std::vector<Eigen::VectorXd>& path) {
    for (std::size_t i = 1; i < path.size(); ++i)
      if (const std::optional<double>* c = checked.find(path[i - 1], path[i]); c && *c)
        found.clearance = std::min(found.clearance.value_or(**c), **c);
    return path;
  };
  if (passes(snapshots.back())) return returned(snapshots.back());
  if (limit.fired()) return std::nullopt;
  // A shortcut free at the tree resolution grazed an obstacle between its
  // samples. Repair: find a smoothing batch whose path passes the final
  // check and whose successor does not (bisection; the unsmoothed path
  // must pass if it comes to that), then smooth on from there for one
  // batch of each pass with every shortcut checked at the final
  // resolution. The full passes at that resolution cost 2-3 times a whole
  // plan in the bin scene, for paths 0-10 % shorter than after one batch.
  std::size_t good = 0, bad = snapshots.size() - 1;
  while (bad - good > 1) {
    const std::size_t mid = (good + bad) / 2;
    if (passes(snapshots[mid]))
      good = mid;
    else
      bad = mid;
  }
  if (good == 0 && !passes(snapshots[good])) return std::nullopt;
  if (limit.expired()) return returned(snapshots[good]);
  std::vector<Eigen::VectorXd> repaired;
  {
    const ScopedResolution fine(*validator, check.resolution);
    PathSmoothing oneBatch = smoothing;
    oneBatch.steps = std::min(smoothing.steps, kBatch);
    repaired = smoothInBatches(si, snapshots[good], oneBatch, stop).back();
  }
  if (passes(repaired)) return returned(repaired);
  return returned(snapshots[good]);
}

double pathLength(const WeightedStateSpace& space, const std::vector<Eigen::VectorXd>& path) {
  double length = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) length += space.distance(path[i - 1], path[i]);
  return length;
}

}  // namespace hfts::planner
