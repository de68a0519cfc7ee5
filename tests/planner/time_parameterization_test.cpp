#include "planner/time_parameterization.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hfts_db/invalid_argument.h"

namespace hfts::planner {
namespace {

using Waypoints = std::vector<Eigen::VectorXd>;

Eigen::VectorXd vec(std::initializer_list<double> values) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(values.size()));
  Eigen::Index i = 0;
  for (double x : values) v[i++] = x;
  return v;
}

/// Rest-to-rest time of one joint-space straight line under per-joint
/// limits: the joint that needs longest decides (bang-bang or trapezoid).
double restToRest(const Eigen::VectorXd& from, const Eigen::VectorXd& to, const Eigen::VectorXd& v,
                  const Eigen::VectorXd& a) {
  const Eigen::VectorXd d = (to - from).cwiseAbs();
  // Along the line every joint moves in proportion: the path's own limits.
  const double length = d.norm();
  double vs = INFINITY, as = INFINITY;
  for (Eigen::Index i = 0; i < d.size(); ++i)
    if (d[i] > 0) {
      vs = std::min(vs, v[i] * length / d[i]);
      as = std::min(as, a[i] * length / d[i]);
    }
  if (length > vs * vs / as) return length / vs + vs / as;
  return 2.0 * std::sqrt(length / as);
}

/// Distance from p to the polyline through the waypoints.
double distanceToPolyline(const Waypoints& w, const Eigen::VectorXd& p) {
  double best = INFINITY;
  for (std::size_t i = 0; i + 1 < w.size(); ++i) {
    const Eigen::VectorXd d = w[i + 1] - w[i];
    const double t = std::clamp((p - w[i]).dot(d) / d.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (w[i] + t * d - p).norm());
  }
  return best;
}

Waypoints randomPath(std::mt19937_64& rng, int dofs, int points) {
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  Waypoints w;
  for (int i = 0; i < points; ++i) {
    Eigen::VectorXd q(dofs);
    for (int j = 0; j < dofs; ++j) q[j] = u(rng);
    w.push_back(q);
  }
  return w;
}

Eigen::VectorXd randomLimits(std::mt19937_64& rng, int dofs, double low, double high) {
  std::uniform_real_distribution<double> u(low, high);
  Eigen::VectorXd l(dofs);
  for (int j = 0; j < dofs; ++j) l[j] = u(rng);
  return l;
}

void expectWithinLimits(const TimeOptimalTrajectory& trajectory, const Eigen::VectorXd& v,
                        const Eigen::VectorXd& a, double rate) {
  for (const TrajectoryPoint& p : trajectory.sample(rate))
    for (Eigen::Index i = 0; i < v.size(); ++i) {
      ASSERT_LE(std::abs(p.velocities[i]), v[i] + 1e-6) << "joint " << i << " at " << p.time;
      ASSERT_LE(std::abs(p.accelerations[i]), a[i] + 1e-6) << "joint " << i << " at " << p.time;
    }
}

TEST(TimeOptimalTrajectory, AStraightLineTakesTheAnalyticMinimumTime) {
  const Eigen::VectorXd v = vec({1.0, 2.0, 0.5}), a = vec({3.0, 1.0, 2.0});
  for (const Waypoints& w : {Waypoints{vec({0, 0, 0}), vec({2, 1, 0.5})},             // trapezoid
                             Waypoints{vec({0, 0, 0}), vec({0.05, -0.02, 0.01})}}) {  // bang-bang
    const TimeOptimalTrajectory trajectory(w, v, a);
    // Exact but for the grid interval where the acceleration switches.
    const double optimum = restToRest(w[0], w[1], v, a);
    EXPECT_GE(trajectory.duration(), optimum - 1e-12);
    EXPECT_NEAR(trajectory.duration(), optimum, 1e-4 * optimum);
    EXPECT_EQ(trajectory.timeScale(), 1.0);
  }
}

TEST(TimeOptimalTrajectory, WithoutBlendsItStopsAtEveryCornerAndFollowsThePathExactly) {
  std::mt19937_64 rng(7);
  const Waypoints w = randomPath(rng, 4, 6);
  const Eigen::VectorXd v = randomLimits(rng, 4, 0.5, 2), a = randomLimits(rng, 4, 1, 5);
  TrajectoryOptions exact;
  exact.max_deviation = 0.0;
  const TimeOptimalTrajectory trajectory(w, v, a, exact);
  double expected = 0.0;
  for (std::size_t i = 0; i + 1 < w.size(); ++i) expected += restToRest(w[i], w[i + 1], v, a);
  EXPECT_NEAR(trajectory.duration(), expected, 1e-5);
  EXPECT_EQ(trajectory.deviation(), 0.0);
  for (const TrajectoryPoint& p : trajectory.sample(500))
    EXPECT_LT(distanceToPolyline(w, p.positions), 1e-9) << p.time;
}

TEST(TimeOptimalTrajectory, RandomPathsStayWithinTheLimitsAndNearThePath) {
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    const int dofs = 1 + trial % 13;
    const Waypoints w = randomPath(rng, dofs, 2 + trial % 9);
    const Eigen::VectorXd v = randomLimits(rng, dofs, 0.3, 8), a = randomLimits(rng, dofs, 0.5, 20);
    TrajectoryOptions options;
    options.max_deviation = std::uniform_real_distribution<double>(0.0, 0.1)(rng);
    const TimeOptimalTrajectory trajectory(w, v, a, options);
    SCOPED_TRACE("trial " + std::to_string(trial));
    expectWithinLimits(trajectory, v, a, 1000);
    EXPECT_LE(trajectory.deviation(), options.max_deviation + 1e-12);
    EXPECT_LT(trajectory.timeScale(), 1.02);
    for (const TrajectoryPoint& p : trajectory.sample(200))
      ASSERT_LE(distanceToPolyline(w, p.positions), trajectory.deviation() + 1e-9) << p.time;
  }
}

TEST(TimeOptimalTrajectory, AtAlmostEveryInstantSomeJointIsAtALimit) {
  // What makes a trajectory time-optimal: no moment where every joint
  // could have gone faster (but at the grid intervals where it switches).
  std::mt19937_64 rng(13);
  for (int trial = 0; trial < 5; ++trial) {
    const Waypoints w = randomPath(rng, 6, 6);
    const Eigen::VectorXd v = randomLimits(rng, 6, 0.5, 4), a = randomLimits(rng, 6, 1, 10);
    const TimeOptimalTrajectory trajectory(w, v, a);
    int saturated = 0, samples = 0;
    for (const TrajectoryPoint& p : trajectory.sample(1000)) {
      const double use = std::max((p.velocities.cwiseAbs().array() / v.array()).maxCoeff(),
                                  (p.accelerations.cwiseAbs().array() / a.array()).maxCoeff());
      // The last uniform slow-down takes the same share off every limit.
      saturated += use > 0.99 / (trajectory.timeScale() * trajectory.timeScale()) ? 1 : 0;
      ++samples;
    }
    EXPECT_GT(saturated, 0.97 * samples) << "trial " << trial;
  }
}

TEST(TimeOptimalTrajectory, StartsAndEndsAtRestOnTheEndWaypointsWithTimeIncreasing) {
  std::mt19937_64 rng(3);
  const Waypoints w = randomPath(rng, 13, 8);
  const Eigen::VectorXd v = randomLimits(rng, 13, 1, 6), a = randomLimits(rng, 13, 2, 10);
  const TimeOptimalTrajectory trajectory(w, v, a);
  const std::vector<TrajectoryPoint> points = trajectory.sample(100);
  ASSERT_GE(points.size(), 2u);
  EXPECT_EQ(points.front().time, 0.0);
  EXPECT_DOUBLE_EQ(points.back().time, trajectory.duration());
  EXPECT_LT((points.front().positions - w.front()).norm(), 1e-12);
  EXPECT_LT((points.back().positions - w.back()).norm(), 1e-9);
  EXPECT_EQ(points.front().velocities.norm(), 0.0);
  EXPECT_EQ(points.back().velocities.norm(), 0.0);
  for (std::size_t i = 1; i < points.size(); ++i) {
    EXPECT_GT(points[i].time, points[i - 1].time);
    EXPECT_LE(points[i].time - points[i - 1].time, 0.01 + 1e-12);
  }
}

TEST(TimeOptimalTrajectory, VelocitiesAndAccelerationsAreTheDerivativesOfThePositions) {
  std::mt19937_64 rng(5);
  const Waypoints w = randomPath(rng, 6, 5);
  const Eigen::VectorXd v = randomLimits(rng, 6, 1, 3), a = randomLimits(rng, 6, 2, 6);
  TrajectoryOptions options;
  options.max_deviation = 0.05;
  const TimeOptimalTrajectory trajectory(w, v, a, options);
  const double h = 1e-6;
  for (double t = 0.01; t < trajectory.duration() - 0.01; t += 0.0137) {
    const TrajectoryPoint p = trajectory.at(t);
    const Eigen::VectorXd slope =
        (trajectory.at(t + h).positions - trajectory.at(t - h).positions) / (2 * h);
    EXPECT_LT((slope - p.velocities).norm(), 1e-5) << t;
    // Accelerations jump between grid intervals: compare one-sided.
    const Eigen::VectorXd change = (trajectory.at(t + h).velocities - p.velocities) / h;
    const Eigen::VectorXd before = (p.velocities - trajectory.at(t - h).velocities) / h;
    EXPECT_LT(std::min((change - p.accelerations).norm(), (before - p.accelerations).norm()),
              1e-3 * (1 + p.accelerations.norm()))
        << t;
  }
}

TEST(TimeOptimalTrajectory, BlendsSaveTimeAndAFinerGridChangesLittle) {
  std::mt19937_64 rng(9);
  const Waypoints w = randomPath(rng, 7, 7);
  const Eigen::VectorXd v = randomLimits(rng, 7, 1, 4), a = randomLimits(rng, 7, 2, 8);
  TrajectoryOptions stops, blends, fine;
  stops.max_deviation = 0.0;
  blends.max_deviation = fine.max_deviation = 0.05;
  fine.path_step = 1e-4;
  const double stopping = TimeOptimalTrajectory(w, v, a, stops).duration();
  const double blended = TimeOptimalTrajectory(w, v, a, blends).duration();
  const double finer = TimeOptimalTrajectory(w, v, a, fine).duration();
  EXPECT_LT(blended, stopping);
  EXPECT_NEAR(finer, blended, 0.01 * blended);
  EXPECT_LE(finer, blended + 1e-9);
}

TEST(TimeOptimalTrajectory, ATurnBackStopsThereAndRepeatsAreIgnored) {
  const Eigen::VectorXd v = vec({1, 1}), a = vec({2, 2});
  const Waypoints w{vec({0, 0}), vec({1, 0}), vec({1, 0}), vec({0.5, 0})};
  const TimeOptimalTrajectory trajectory(w, v, a);
  EXPECT_NEAR(trajectory.duration(), restToRest(w[0], w[1], v, a) + restToRest(w[2], w[3], v, a),
              1e-9);
  EXPECT_EQ(trajectory.deviation(), 0.0);
}

TEST(TimeOptimalTrajectory, OneConfigurationIsATrajectoryOfNoTime) {
  const Waypoints w{vec({0.5, 1}), vec({0.5, 1})};
  const TimeOptimalTrajectory trajectory(w, vec({1, 1}), vec({1, 1}));
  EXPECT_EQ(trajectory.duration(), 0.0);
  const std::vector<TrajectoryPoint> points = trajectory.sample(100);
  ASSERT_EQ(points.size(), 1u);
  EXPECT_EQ(points[0].positions, w[0]);
  EXPECT_EQ(points[0].velocities.norm(), 0.0);
}

TEST(TimeOptimalTrajectory, BadInputIsRefusedByName) {
  const Eigen::VectorXd one = vec({1, 1});
  const auto field = [&](const Waypoints& w, const Eigen::VectorXd& v, const Eigen::VectorXd& a,
                         TrajectoryOptions o = {}) {
    try {
      TimeOptimalTrajectory(w, v, a, o);
    } catch (const InvalidArgument& e) {
      return e.field();
    }
    return std::string("(accepted)");
  };
  const Waypoints ok{vec({0, 0}), vec({1, 1})};
  EXPECT_EQ(field({}, one, one), "waypoints");
  EXPECT_EQ(field({vec({0, 0}), vec({1, 1, 1})}, one, one), "waypoints[1]");
  EXPECT_EQ(field({vec({0, 0}), vec({NAN, 1})}, one, one), "waypoints[1]");
  EXPECT_EQ(field(ok, vec({1}), one), "maxVelocity");
  EXPECT_EQ(field(ok, one, vec({1, 0})), "maxAcceleration");
  EXPECT_EQ(field(ok, one, vec({1, INFINITY})), "maxAcceleration");
  TrajectoryOptions o;
  o.max_deviation = -1;
  EXPECT_EQ(field(ok, one, one, o), "max_deviation");
  o = {};
  o.path_step = 0;
  EXPECT_EQ(field(ok, one, one, o), "path_step");
  EXPECT_EQ(field(ok, one, one), "(accepted)");
  EXPECT_THROW(TimeOptimalTrajectory(ok, one, one).sample(0), InvalidArgument);
}

}  // namespace
}  // namespace hfts::planner
