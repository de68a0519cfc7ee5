// Kunz and Stilman's blended path with a TOPP-RA time law
// (planner/time_parameterization.h, docs/trajectories.md).

#include "planner/time_parameterization.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/invalid_argument.h"

namespace hfts::planner {
namespace {

using Segment = TimeOptimalTrajectory::Segment;

constexpr double kPi = 3.14159265358979323846;
/// Waypoints closer than this are one (rad).
constexpr double kSamePoint = 1e-9;
/// Corners that turn less than this go straight on; more than pi minus
/// this turn back, where no blend fits: the robot stops there.
constexpr double kStraight = 1e-9, kTurnBack = 1e-6;
/// Grid intervals: at least this many per segment, and on a blend at most
/// this angle each (rad), so a sharp corner's small arc is resolved.
constexpr int kMinIntervals = 2;
constexpr double kMaxArcStep = 0.05;
/// Joint i with |f'_i| below this does not bound the path acceleration;
/// its limit becomes a bound on the path velocity alone.
constexpr double kFlat = 1e-9;
/// Samples per grid interval when the limits are certified on a blend.
constexpr int kCertifySamples = 32;
/// Relative excess over a limit that counts as rounding.
constexpr double kRounding = 1e-9;

Eigen::VectorXd tangent(const Segment& g, double u) {
  if (!g.arc) return g.x;
  const double phi = u / g.radius;
  return -std::sin(phi) * g.x + std::cos(phi) * g.y;
}

Eigen::VectorXd curvature(const Segment& g, double u) {
  if (!g.arc) return Eigen::VectorXd::Zero(g.x.size());
  const double phi = u / g.radius;
  return -(std::cos(phi) * g.x + std::sin(phi) * g.y) / g.radius;
}

/// Joint velocity and acceleration at u along g, with path velocity
/// `speed` and path acceleration `accel`: f' sd and f' sdd + f'' sd^2.
void derivatives(const Segment& g, double u, double speed, double accel, Eigen::VectorXd& velocity,
                 Eigen::VectorXd& acceleration) {
  velocity = tangent(g, u);
  acceleration = velocity * accel + curvature(g, u) * (speed * speed);
  velocity *= speed;
}

Eigen::VectorXd point(const Segment& g, double u) {
  if (!g.arc) return g.origin + u * g.x;
  const double phi = u / g.radius;
  return g.origin + g.radius * (std::cos(phi) * g.x + std::sin(phi) * g.y);
}

void checkInputs(const std::vector<Eigen::VectorXd>& waypoints, const Eigen::VectorXd& velocity,
                 const Eigen::VectorXd& acceleration, const TrajectoryOptions& options) {
  if (waypoints.empty()) throw InvalidArgument("waypoints", "must not be empty");
  const Eigen::Index n = waypoints.front().size();
  if (n == 0) throw InvalidArgument("waypoints", "hold configurations of size 0");
  for (std::size_t i = 0; i < waypoints.size(); ++i) {
    const std::string name = "waypoints[" + std::to_string(i) + "]";
    if (waypoints[i].size() != n)
      throw InvalidArgument(name, "has " + std::to_string(waypoints[i].size()) +
                                      " values, the first waypoint " + std::to_string(n));
    if (!waypoints[i].allFinite()) throw InvalidArgument(name, "holds a non-finite value");
  }
  const auto limits = [n](const Eigen::VectorXd& v, const char* name) {
    if (v.size() != n)
      throw InvalidArgument(
          name, "has " + std::to_string(v.size()) + " values, waypoints have " + std::to_string(n));
    for (Eigen::Index i = 0; i < n; ++i)
      if (!(v[i] > 0.0) || !std::isfinite(v[i]))
        throw InvalidArgument(name, "value " + std::to_string(i) + " must be positive and finite");
  };
  limits(velocity, "maxVelocity");
  limits(acceleration, "maxAcceleration");
  if (!(options.max_deviation >= 0.0) || !std::isfinite(options.max_deviation))
    throw InvalidArgument("max_deviation", "must be >= 0 and finite");
  if (!(options.path_step > 0.0 && options.path_step <= 1.0))
    throw InvalidArgument("path_step", "must be in (0, 1]");
}

/// The waypoints without repeats (consecutive ones closer than kSamePoint).
std::vector<Eigen::VectorXd> distinct(const std::vector<Eigen::VectorXd>& waypoints) {
  std::vector<Eigen::VectorXd> out{waypoints.front()};
  for (const Eigen::VectorXd& w : waypoints)
    if ((w - out.back()).norm() > kSamePoint) out.push_back(w);
  return out;
}

/// Kunz and Stilman's path: straight segments, each corner replaced by the
/// circular arc tangent to both of its segments that passes within
/// `maxDeviation` of the corner and uses at most half of either segment.
/// Returns the largest deviation of an arc.
double blendedPath(const std::vector<Eigen::VectorXd>& w, double maxDeviation,
                   std::vector<Segment>& out) {
  const std::size_t m = w.size();
  std::vector<double> cut(m, 0.0);  // of each side of corner i, along the segments
  std::vector<bool> stop(m, false);
  double deviation = 0.0;
  std::vector<Segment> arcs(m);
  for (std::size_t i = 1; i + 1 < m; ++i) {
    const Eigen::VectorXd in = w[i] - w[i - 1], outgoing = w[i + 1] - w[i];
    const Eigen::VectorXd din = in.normalized(), dout = outgoing.normalized();
    const double angle = std::acos(std::clamp(din.dot(dout), -1.0, 1.0));
    if (angle < kStraight) continue;
    if (maxDeviation == 0.0 || angle > kPi - kTurnBack) {
      stop[i] = true;
      continue;
    }
    const double half = angle / 2.0;
    cut[i] = std::min({in.norm() / 2.0, outgoing.norm() / 2.0,
                       maxDeviation * std::sin(half) / (1.0 - std::cos(half))});
    Segment& a = arcs[i];
    a.arc = true;
    a.radius = cut[i] / std::tan(half);
    a.length = a.radius * angle;
    const Eigen::VectorXd inward = (dout - din * din.dot(dout)).normalized();
    a.origin = w[i] - cut[i] * din + a.radius * inward;
    a.x = -inward;
    a.y = din;
    deviation = std::max(deviation, a.radius * (1.0 / std::cos(half) - 1.0));
  }
  double s = 0.0;
  bool stopNext = false;
  for (std::size_t i = 0; i + 1 < m; ++i) {
    const Eigen::VectorXd d = (w[i + 1] - w[i]).normalized();
    Segment line;
    line.origin = w[i] + cut[i] * d;
    line.x = d;
    line.length = (w[i + 1] - cut[i + 1] * d - line.origin).norm();
    line.stop_at_start = stopNext;
    if (line.length > kSamePoint || out.empty()) {
      line.start = s;
      s += line.length;
      out.push_back(std::move(line));
    }
    stopNext = stop[i + 1];
    if (arcs[i + 1].arc) {
      arcs[i + 1].start = s;
      s += arcs[i + 1].length;
      out.push_back(std::move(arcs[i + 1]));
    }
  }
  return deviation;
}

/// One linear constraint on path acceleration u = sdd and x = sd^2 over a
/// grid interval: a u + b x <= c.
struct Row {
  double a = 0.0, b = 0.0, c = 0.0;
};

/// The limits of one grid interval. Joint i needs |f'_i u + f''_i x| <=
/// a_i at the interval's start (collocation) and, on a blend, also at its
/// end, where x has become x + 2 ds u (TOPP-RA's interpolation scheme: the
/// limits then hold between grid points to second order, not first).
/// Velocities: |f'_i| sqrt(x) <= v_i at the grid points.
class IntervalLimits {
 public:
  double max_x = std::numeric_limits<double>::infinity();  ///< from the velocity limits

  void addJointLimits(const Eigen::VectorXd& d1, const Eigen::VectorXd& d2, double ds,
                      const Eigen::VectorXd& a) {
    for (Eigen::Index i = 0; i < d1.size(); ++i) {
      const double scaled = d1[i] + 2.0 * ds * d2[i];  // x at the end: x + 2 ds u
      add({scaled, d2[i], a[i]});
      add({-scaled, -d2[i], a[i]});
    }
  }

  void addVelocityLimits(const Eigen::VectorXd& d1, const Eigen::VectorXd& v) {
    for (Eigen::Index i = 0; i < d1.size(); ++i)
      if (std::abs(d1[i]) > kFlat) max_x = std::min(max_x, (v[i] / d1[i]) * (v[i] / d1[i]));
  }

  /// The highest path acceleration allowed at x.
  double highest(double x) const {
    double out = std::numeric_limits<double>::infinity();
    for (const Row& r : upper_) out = std::min(out, (r.c - r.b * x) / r.a);
    return out;
  }

  /// The largest x from which some allowed u over a step of `ds` ends at
  /// x' = x + 2 ds u in [0, next]: max x with the allowed accelerations
  /// meeting [-x / 2ds, (next - x) / 2ds], at most max_x; -1 when none.
  double controllable(double ds, double next) const {
    std::vector<Row> lower = lower_, upper = upper_;
    lower.push_back({-1.0, -1.0 / (2.0 * ds), 0.0});  // u >= -x / 2ds
    upper.push_back({1.0, 1.0 / (2.0 * ds), next / (2.0 * ds)});
    double low = 0.0, high = max_x;
    for (const Row& q : lower)
      for (const Row& p : upper) {
        // u >= (c_q - b_q x) / a_q and u <= (c_p - b_p x) / a_p meet when
        // (b_p / a_p - b_q / a_q) x <= c_p / a_p - c_q / a_q.
        const double slope = p.b / p.a - q.b / q.a, room = p.c / p.a - q.c / q.a;
        if (slope > 0.0)
          high = std::min(high, room / slope);
        else if (slope < 0.0)
          low = std::max(low, room / slope);
        else if (room < 0.0)
          return -1.0;
      }
    return low <= high ? high : -1.0;
  }

 private:
  std::vector<Row> lower_, upper_;  ///< a < 0: bounds u from below; a > 0: from above

  void add(const Row& r) {
    if (std::abs(r.a) > kFlat)
      (r.a > 0.0 ? upper_ : lower_).push_back(r);
    else if (r.b > 0.0)  // f'_i ~ 0: the joint's limit bounds x alone
      max_x = std::min(max_x, r.c / r.b);
  }
};

}  // namespace

TimeOptimalTrajectory::TimeOptimalTrajectory(const std::vector<Eigen::VectorXd>& waypoints,
                                             const Eigen::VectorXd& maxVelocity,
                                             const Eigen::VectorXd& maxAcceleration,
                                             const TrajectoryOptions& options)
    : maxVelocity_(maxVelocity), maxAcceleration_(maxAcceleration) {
  checkInputs(waypoints, maxVelocity, maxAcceleration, options);
  const std::vector<Eigen::VectorXd> w = distinct(waypoints);
  if (w.size() == 1) {  // nowhere to go: one knot at rest
    Segment still;
    still.origin = w.front();
    still.x = Eigen::VectorXd::Zero(w.front().size());
    segments_.push_back(std::move(still));
    knots_.push_back({});
    return;
  }
  deviation_ = blendedPath(w, options.max_deviation, segments_);
  solveTimeLaw(options);
  certifyLimits();
}

void TimeOptimalTrajectory::solveTimeLaw(const TrajectoryOptions& options) {
  // The grid: every segment cut into equal intervals, its start a grid point.
  for (std::size_t g = 0; g < segments_.size(); ++g) {
    const Segment& seg = segments_[g];
    double steps = std::ceil(seg.length / options.path_step);
    if (seg.arc) steps = std::max(steps, std::ceil(seg.length / seg.radius / kMaxArcStep));
    const int n = std::max(kMinIntervals, static_cast<int>(steps));
    for (int j = 0; j < n; ++j) knots_.push_back({seg.start + seg.length * j / n, 0, 0, 0, g});
  }
  const Segment& last = segments_.back();
  knots_.push_back({last.start + last.length, 0, 0, 0, segments_.size() - 1});

  // Limits of each interval (a blend's end is bounded by the interval
  // before it); a corner without a blend is a stop.
  const std::size_t n = knots_.size();
  std::vector<IntervalLimits> limits(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Segment& seg = segments_[knots_[k].segment];
    const double u = knots_[k].s - seg.start;
    IntervalLimits& l = limits[k];
    l.addVelocityLimits(tangent(seg, u), maxVelocity_);
    if (k + 1 < n) {
      l.addJointLimits(tangent(seg, u), curvature(seg, u), 0.0, maxAcceleration_);
      const double ds = knots_[k + 1].s - knots_[k].s;
      if (seg.arc)
        l.addJointLimits(tangent(seg, u + ds), curvature(seg, u + ds), ds, maxAcceleration_);
    }
    if (k > 0 && knots_[k - 1].segment != knots_[k].segment) {
      const Segment& before = segments_[knots_[k - 1].segment];
      l.addVelocityLimits(tangent(before, before.length), maxVelocity_);
      if (seg.stop_at_start) l.max_x = 0.0;
    }
  }

  // Backward pass: the largest controllable x = sd^2 at each point, from
  // which the robot can still come to rest at the end.
  std::vector<double> reachable(n, 0.0);
  for (std::size_t k = n - 1; k-- > 0;) {
    const double ds = knots_[k + 1].s - knots_[k].s;
    reachable[k] = std::max(0.0, limits[k].controllable(ds, reachable[k + 1]));
  }
  // Forward pass: from rest, the highest acceleration that stays controllable.
  double x = 0.0, time = 0.0;
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const double ds = knots_[k + 1].s - knots_[k].s;
    const double next = std::clamp(std::min(x + 2.0 * ds * limits[k].highest(x), reachable[k + 1]),
                                   0.0, reachable[k + 1]);
    Knot& knot = knots_[k];
    knot.speed = std::sqrt(x);
    knot.acceleration = (next - x) / (2.0 * ds);
    knot.time = time;
    time += 2.0 * ds / (knot.speed + std::sqrt(next));
    if (!std::isfinite(time))
      throw std::logic_error("time law stands still at s = " + std::to_string(knot.s));
    x = next;
  }
  knots_.back().time = time;
  duration_ = time;
}

void TimeOptimalTrajectory::certifyLimits() {
  // On a straight segment the joint acceleration is constant between two
  // knots and the velocity monotonic: the knots bound them exactly. On a
  // blend both change with s; samples plus a bound of each over the gap h
  // to the nearest sample bound them. Velocity f'_i sd: |f'_i| changes by
  // at most h / r (|f''| = 1/r) and x = sd^2, linear in s, by at most
  // 2 |sdd| h, so |f'_i sd| <= (|f'_i| + h / r) sqrt(x + 2 |sdd| h). (A
  // bound through d(sd)/ds = sdd / sd has no limit where the time law
  // nearly stops on a blend.) Acceleration: Lipschitz in s, |f'''| <= 1/r^2.
  double velocityRatio = 0.0, accelerationRatio = 0.0;
  Eigen::VectorXd v, a;
  for (std::size_t k = 0; k + 1 < knots_.size(); ++k) {
    const Knot& from = knots_[k];
    const Knot& to = knots_[k + 1];
    const Segment& seg = segments_[from.segment];
    const int samples = seg.arc ? kCertifySamples : 1;
    double tangentSlack = 0.0, xSlack = 0.0, accelerationSlack = 0.0;
    if (seg.arc) {
      const double h = (to.s - from.s) / samples / 2.0, r = seg.radius;
      const double fastest = std::max(from.speed, to.speed);
      tangentSlack = h / r;
      xSlack = 2.0 * std::abs(from.acceleration) * h;
      accelerationSlack = h * (3.0 * std::abs(from.acceleration) / r + fastest * fastest / (r * r));
    }
    for (int j = 0; j <= samples; ++j) {
      const double s = from.s + (to.s - from.s) * j / samples;
      const double x =
          std::max(0.0, from.speed * from.speed + 2.0 * from.acceleration * (s - from.s));
      derivatives(seg, s - seg.start, std::sqrt(x), from.acceleration, v, a);
      const double speed = std::sqrt(x + xSlack);
      velocityRatio =
          std::max(velocityRatio, ((tangent(seg, s - seg.start).cwiseAbs().array() + tangentSlack) *
                                   speed / maxVelocity_.array())
                                      .maxCoeff());
      accelerationRatio = std::max(
          accelerationRatio,
          ((a.cwiseAbs().array() + accelerationSlack) / maxAcceleration_.array()).maxCoeff());
    }
  }
  // Rounding alone (the grid points sit exactly on the limits) is no reason.
  const double needed = std::max(velocityRatio, std::sqrt(accelerationRatio));
  scale_ = needed > 1.0 + kRounding ? needed : 1.0;
  duration_ *= scale_;
}

TrajectoryPoint TimeOptimalTrajectory::at(double t) const {
  const double unscaled = std::clamp(t / scale_, 0.0, knots_.back().time);
  auto next = std::upper_bound(knots_.begin(), knots_.end(), unscaled,
                               [](double v, const Knot& k) { return v < k.time; });
  const Knot& from = next == knots_.begin() ? knots_.front() : *(next - 1);
  const bool end = next == knots_.end();
  const double tau = end ? 0.0 : unscaled - from.time;
  const Segment& seg = segments_[from.segment];
  double s = from.s + from.speed * tau + 0.5 * from.acceleration * tau * tau;
  double speed = from.speed + from.acceleration * tau;
  if (!end) s = std::min(s, next->s);
  if (end) speed = 0.0;
  const double accel = end ? 0.0 : from.acceleration;
  TrajectoryPoint p;
  p.time = std::clamp(t, 0.0, duration_);
  p.positions = point(seg, s - seg.start);
  derivatives(seg, s - seg.start, speed / scale_, accel / (scale_ * scale_), p.velocities,
              p.accelerations);
  return p;
}

double TimeOptimalTrajectory::sampleCount(double rate) const {
  // sample()'s loop: floor(duration rate) + 1 states, and the end state
  // unless the last of them is already at the end (or there is no end).
  const double steps = std::floor(duration_ * rate);
  return steps + 1.0 + (duration_ > 0.0 && steps / rate < duration_ ? 1.0 : 0.0);
}

std::vector<TrajectoryPoint> TimeOptimalTrajectory::sample(double rate) const {
  if (!(rate > 0.0) || !std::isfinite(rate))
    throw InvalidArgument("rate", "must be positive and finite");
  if (!(sampleCount(rate) <= static_cast<double>(kMaxTrajectorySamples)))
    throw InvalidArgument("rate", "a state every 1/" + std::to_string(rate) + " s over " +
                                      std::to_string(duration_) + " s is more than " +
                                      std::to_string(kMaxTrajectorySamples) + " states");
  std::vector<TrajectoryPoint> out;
  const auto steps = static_cast<std::size_t>(std::floor(duration_ * rate));
  for (std::size_t i = 0; i <= steps; ++i) {
    const double t = static_cast<double>(i) / rate;
    if (t < duration_ || i == 0) out.push_back(at(t));
  }
  if (duration_ > 0.0) out.push_back(at(duration_));
  return out;
}

}  // namespace hfts::planner
