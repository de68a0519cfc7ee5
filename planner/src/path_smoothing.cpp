#include "planner/path_smoothing.h"

#include <algorithm>
#include <chrono>
#include <functional>
#include <optional>
#include <random>
#include <stdexcept>
#include <utility>

namespace hfts::planner {

namespace ob = ompl::base;

namespace {

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

using Path = std::vector<Eigen::VectorXd>;

/// `path` without the interior vertices that lie on the straight segment
/// between their neighbours: a tree's extension adds a node every step
/// along one line, so a found path has many times the vertices of its
/// corners. The same configurations, fewer vertices, no check.
Path withoutStraightVertices(const Path& path) {
  // Directions that agree to this are one line: the steps of an extension
  // differ by rounding only.
  constexpr double kStraight = 1e-9;
  Path out;
  out.reserve(path.size());
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (i > 0 && i + 1 < path.size()) {
      const Eigen::VectorXd in = path[i] - out.back();
      const Eigen::VectorXd on = path[i + 1] - path[i];
      const double inNorm = in.norm(), onNorm = on.norm();
      if (inNorm > 0.0 && onNorm > 0.0 && (in / inNorm - on / onNorm).norm() < kStraight) continue;
    }
    out.push_back(path[i]);
  }
  return out;
}

/// Greedy vertex reduction: from each kept vertex, straight to the
/// farthest later vertex the motion reaches free. Deterministic; a free
/// motion is checked once per kept vertex, and a colliding one usually
/// stops after its first batch of states (bisection order); n vertices
/// cost at most n (n - 1) / 2 checks. `stop` is polled from the
/// second kept vertex on (the first is reduced even when it has fired: a
/// shorter path is cheaper to re-check); once it fires, the rest of the
/// path stays as it is.
Path reducedVertices(const Path& path, const CollisionMotionValidator& validator,
                     const std::function<bool()>& stop) {
  Path out{path.front()};
  std::size_t from = 0;
  while (from + 1 < path.size()) {
    std::size_t to = from + 1;
    if (from == 0 || !stop())
      for (to = path.size() - 1; to > from + 1; --to)
        if (validator.checkMotion(path[from], path[to], validator.resolution())) break;
    out.push_back(path[to]);
    from = to;
  }
  return out;
}

/// The motion validator of `si`, which checks the shortcuts.
CollisionMotionValidator& motionValidator(const ob::SpaceInformationPtr& si) {
  auto* validator = dynamic_cast<CollisionMotionValidator*>(si->getMotionValidator().get());
  if (validator == nullptr)
    throw std::invalid_argument("path smoothing needs a CollisionMotionValidator");
  return *validator;
}

/// A point on a path: at vertex `lo` when lo == hi, else between vertices
/// lo and hi = lo + 1.
struct PathPoint {
  std::size_t lo = 0, hi = 0;
  Eigen::VectorXd q;
};

/// Sets `p` to the point at arc length `s` of `path` (cumulative lengths
/// `arc`), snapped to a vertex within `snap` (in place: p.q keeps its
/// storage from draw to draw).
void pointAt(const Path& path, const std::vector<double>& arc, double s, double snap,
             PathPoint& p) {
  const auto next = static_cast<std::size_t>(
      std::min<std::ptrdiff_t>(std::lower_bound(arc.begin(), arc.end(), s) - arc.begin(),
                               static_cast<std::ptrdiff_t>(arc.size()) - 1));
  if (next == 0 || arc[next] - s < snap) {
    p.lo = p.hi = next;
    p.q = path[next];
  } else if (s - arc[next - 1] < snap) {
    p.lo = p.hi = next - 1;
    p.q = path[next - 1];
  } else {
    const double t = (s - arc[next - 1]) / (arc[next] - arc[next - 1]);
    p.lo = next - 1;
    p.hi = next;
    p.q = path[next - 1] + (path[next] - path[next - 1]) * t;
  }
}

/// Random shortcuts, `attempts` of them, as OMPL's shortcutPath draws
/// them (a point along the path, a second within a third of the path's
/// length of it, both snapped to a vertex within 0.5 % of it), joined
/// straight when the motion is free. A pair whose straight line would
/// save less than kMinSaving of the path's length is not checked: near
/// the end of smoothing most drawn pairs lie on almost straight stretches,
/// and their checks cost a free motion's full length for nothing. Returns
/// whether the path got shorter.
bool shortcut(Path& path, const CollisionMotionValidator& validator,
              const WeightedStateSpace& space, std::mt19937& rng, unsigned attempts) {
  constexpr double kRange = 0.33, kSnap = 0.005, kMinSaving = 1e-3;
  std::vector<double> arc(path.size(), 0.0);
  const auto measure = [&] {
    arc.assign(path.size(), 0.0);
    for (std::size_t i = 1; i < path.size(); ++i)
      arc[i] = arc[i - 1] + space.distance(path[i - 1], path[i]);
  };
  measure();
  bool shortened = false;
  PathPoint a, b;
  for (unsigned attempt = 0; attempt < attempts && path.size() > 2; ++attempt) {
    const double length = arc.back();
    const double s0 = std::uniform_real_distribution<double>(0.0, length)(rng);
    const double s1 = std::uniform_real_distribution<double>(
        std::max(0.0, s0 - kRange * length), std::min(length, s0 + kRange * length))(rng);
    pointAt(path, arc, std::min(s0, s1), kSnap * length, a);
    pointAt(path, arc, std::max(s0, s1), kSnap * length, b);
    if (b.hi < a.lo + 2) continue;  // no vertex between them to cut
    const double along =
        arc[b.lo] - arc[a.hi] + space.distance(a.q, path[a.hi]) + space.distance(path[b.lo], b.q);
    if (along - space.distance(a.q, b.q) < kMinSaving * length) continue;
    if (!validator.checkMotion(a.q, b.q, validator.resolution())) continue;
    // The vertices strictly between the two points give way to them.
    const auto first = path.begin() + static_cast<std::ptrdiff_t>(a.lo) + 1;
    path.erase(first, path.begin() + static_cast<std::ptrdiff_t>(b.hi));
    std::size_t at = a.lo + 1;
    if (a.hi != a.lo) path.insert(path.begin() + static_cast<std::ptrdiff_t>(at++), a.q);
    if (b.hi != b.lo) path.insert(path.begin() + static_cast<std::ptrdiff_t>(at), b.q);
    measure();
    shortened = true;
  }
  return shortened;
}

/// The smoothing passes on `path`: the path after each step that changed
/// it, the first being `path` itself. Straight vertices dropped, the
/// greedy vertex reduction, then shortcuts in batches.
std::vector<Path> smoothInBatches(const ob::SpaceInformationPtr& si, const Path& path,
                                  const PathSmoothing& smoothing,
                                  const std::function<bool()>& stop) {
  std::vector<Path> snapshots{path};
  if (path.size() < 3 || smoothing.steps == 0) return snapshots;
  const auto keep = [&](Path next) {
    if (next != snapshots.back()) snapshots.push_back(std::move(next));
  };
  keep(withoutStraightVertices(path));
  const auto& validator = motionValidator(si);
  keep(reducedVertices(snapshots.back(), validator, stop));
  std::mt19937 rng(smoothing.seed);
  const WeightedStateSpace& space = weightedSpace(si);
  // Shortcutting ends once two batches in a row shortened nothing.
  constexpr unsigned kIdleBatches = 2;
  unsigned idle = 0;
  Path current = snapshots.back();
  for (unsigned done = 0; done < smoothing.steps && !stop() && idle < kIdleBatches;
       done += kBatch) {
    if (shortcut(current, validator, space, rng, std::min(kBatch, smoothing.steps - done))) {
      keep(current);
      idle = 0;
    } else {
      ++idle;
    }
  }
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
  CollisionMotionValidator& validator = motionValidator(si);
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
    return validWithin(validator, path, check, smoothing.last_rule, limit, checked, found);
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
  // must pass if it comes to that), then smooth on from there (the
  // vertex reduction and one batch of shortcuts) with every change checked
  // at the final resolution. The full passes at that resolution cost 2-3 times a whole
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
    const ScopedResolution fine(validator, check.resolution);
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
