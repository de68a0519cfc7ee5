#include "planner/time_parameterization.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/invalid_argument.h"

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

TEST(TimeOptimalTrajectory, ABlendStartingNearRestTakesNoLongerThanStopping) {
  // A Panda plan's approach (arm and gripper; found by a planner run that
  // ran out of memory sampling it): the certification's slack once divided
  // by a knot speed of almost 0 and slowed it by a factor of 417,233.
  const Waypoints w{
      vec({0, -0.78539816339744828, 0, -2.3561944901923448, 0, 1.5707963267948966,
           0.78539816339744828, 0.040000000000000001}),
      vec({-0.00010192206480324836, -0.75812055836357439, 0.023768916541664575, -2.3375635899822416,
           -0.023955806466068867, 1.5704536134110851, 0.76440319552179836, 0.039990012270410276}),
      vec({-0.0005652172366939301, -0.73144048726156119, 0.045997319163454661, -2.3203450595420043,
           -0.047419284641391363, 1.5700280918830589, 0.74397702723183612, 0.039978580939775583}),
      vec({-0.0012893056080445944, -0.69920809973067799, 0.072390566581865837, -2.2999972260361536,
           -0.0757803480701702, 1.5694731865981277, 0.71934925226787616, 0.039964019137123226}),
      vec({-0.0023265605194682185, -0.66032209726954472, 0.10384392982556814, -2.2758547100921942,
           -0.10998348864477227, 1.5687449444145218, 0.68968275035562887, 0.039945507651326109}),
      vec({-0.0044465634934912771, -0.59912982733731335, 0.15251783051396145, -2.2388504009145396,
           -0.16364699461322552, 1.5673399910989589, 0.64311838225302898, 0.039912413926219796}),
      vec({-0.01821882109067683, -0.26132398989425926, 0.41772982740892972, -2.0387591704795578,
           -0.45921376438838968, 1.5584855564106241, 0.38657259835326696, 0.039712910526962998}),
      vec({-0.026201978080092163, -0.071525730984362379, 0.56632761228184669, -1.926832811824587,
           -0.6251995045261951, 1.5533804867194991, 0.24249100136115492, 0.039598826383236529}),
      vec({-0.037897916482259833, 0.092005450802629812, 0.68623983769689045, -1.8401466954425791,
           -0.76663667191491136, 1.5464240265236433, 0.1195328171187888, 0.039461382643008067}),
      vec({-0.052896548309299032, 0.23771511156480302, 0.78541426836323525, -1.7721413022097052,
           -0.89114503653946442, 1.5377839480517006, 0.011096810737150839, 0.03930156509112382}),
      vec({-0.057285603878801876, 0.26703389826790208, 0.80332368095205076, -1.7610564056335387,
           -0.91565250122119146, 1.5352512809569974, -0.010396024568027622, 0.039257307122654454}),
      vec({-0.071218542479093178, 0.35828458974274091, 0.85866020631740003, -1.7270710720373161,
           -0.99181921736781664, 1.5272101368914188, -0.077224811719687481, 0.03911714441022264}),
      vec({-0.13950657695701504, 0.78719350634340635, 1.1146429758518603, -1.5725939810590104,
           -1.3486942961537671, 1.487778657486706, -0.39067947987343576, 0.038433417792802078}),
      vec({-0.27185868808282077, 1.5252301999636084, 1.5334168831225654, -1.3346208515332463,
           -1.9567127760896739, 1.4112166237499439, -0.926538134798365, 0.037124206265410055}),
      vec({-0.4214726308643838, 1.6136236846628675, 1.5863481114868647, -1.4203028455722224,
           -1.9109434551039119, 1.2770597382384967, -0.95987897319552007, 0.034628160385350229}),
      vec({-0.47491112949952613, 1.6428110348960663, 1.6028130093119906, -1.4521658700084781,
           -1.8936659541244736, 1.2296292260639679, -0.96901563973918869, 0.033684566434677161}),
      vec({-0.60922789590343307, 1.7133299344711368, 1.6412872513912666, -1.5337545984904606,
           -1.8491307353677748, 1.1109941513014352, -0.98867585845809869, 0.031250785204719266}),
      vec({-0.68111480949254277, 1.7507881862437422, 1.6615883778564702, -1.5775711119727871,
           -1.8251846508134841, 1.0475581097364821, -0.99886824865609081, 0.029942019252354683}),
      vec({-0.70772695744168879, 1.7588848421436762, 1.662694873116989, -1.5971400333904429,
           -1.8143090106119917, 1.0253986432502649, -0.99586433092109428, 0.029330438981439153}),
      vec({-0.71625924551508791, 1.7627999999999999, 1.6558552990336841, -1.6009781712686242,
           -1.8111297471171501, 1.0186497844983802, -0.99586433092109428, 0.015002344633519977}),
  };
  const Eigen::VectorXd v = vec({2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61, 0.1});
  const Eigen::VectorXd a = vec({15, 7.5, 10, 12.5, 15, 20, 20, 0.5});
  TrajectoryOptions exact;
  exact.max_deviation = 0.0;
  const double stopping = TimeOptimalTrajectory(w, v, a, exact).duration();
  const TimeOptimalTrajectory blended(w, v, a);
  EXPECT_LT(blended.timeScale(), 1.05);
  EXPECT_LE(blended.duration(), stopping);
  expectWithinLimits(blended, v, a, 1000);
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

TEST(TimeOptimalTrajectory, SampleCountIsWhatSampleGives) {
  const Eigen::VectorXd v = vec({1, 1}), a = vec({2, 2});
  // 1 rad rest to rest at these limits: 1.5 s, a whole number of steps at
  // 2 and 10 per second (the end state is then one of the steps).
  const TimeOptimalTrajectory line({vec({0, 0}), vec({1, 0})}, v, a);
  const TimeOptimalTrajectory still({vec({0, 0}), vec({0, 0})}, v, a);
  const TimeOptimalTrajectory blended({vec({0, 0}), vec({1, 0}), vec({1, 1}), vec({0.3, 2})}, v, a);
  for (const TimeOptimalTrajectory* t : {&line, &still, &blended})
    for (const double rate : {0.5, 2.0, 3.0, 10.0, 100.0, 997.0}) {
      SCOPED_TRACE("duration " + std::to_string(t->duration()) + " rate " + std::to_string(rate));
      EXPECT_EQ(t->sampleCount(rate), static_cast<double>(t->sample(rate).size()));
    }
  EXPECT_NEAR(line.duration(), 1.5, 1e-6);
}

TEST(TimeOptimalTrajectory, TooManyStatesAreRefusedNotAllocated) {
  // 100 rad at 0.01 rad/s: about 10,000 s; at 100 states per second
  // that is a million and two.
  const TimeOptimalTrajectory slow({vec({0, 0}), vec({100, 0})}, vec({0.01, 0.01}), vec({1, 1}));
  EXPECT_GT(slow.duration(), 9999.0);
  EXPECT_EQ(slow.sample(1.0).size(), static_cast<std::size_t>(slow.sampleCount(1.0)));
  EXPECT_GT(slow.sampleCount(100.0), static_cast<double>(kMaxTrajectorySamples));
  try {
    slow.sample(100.0);
    ADD_FAILURE() << "more than kMaxTrajectorySamples states were sampled";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.field(), "rate");
    EXPECT_NE(std::string(e.what()).find("more than 1000000 states"), std::string::npos)
        << e.what();
  }
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
