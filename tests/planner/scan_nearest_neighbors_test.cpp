#include "scan_nearest_neighbors.h"

#include <gtest/gtest.h>

#include <deque>
#include <limits>
#include <random>
#include <vector>

namespace hfts::planner {
namespace {

struct Point {
  Eigen::VectorXd q;
};

/// Random points in [-3, 3]^13 in clusters (like tree nodes, which lie
/// along paths), weights in [0.2, 2].
struct Fixture {
  explicit Fixture(std::size_t count, unsigned seed = 1)
      : rng(seed), metric(randomWeights()), nn(metric) {
    std::normal_distribution<double> step(0.0, 0.1);
    Eigen::VectorXd at = randomPoint();
    for (std::size_t i = 0; i < count; ++i) {
      if (i % 40 == 0) at = randomPoint();
      for (Eigen::Index d = 0; d < at.size(); ++d) at(d) += step(rng);
      points.push_back({at});
      nn.add(&points.back());
    }
  }
  Eigen::VectorXd randomPoint() {
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    Eigen::VectorXd q(13);
    for (Eigen::Index d = 0; d < q.size(); ++d) q(d) = u(rng);
    return q;
  }
  Eigen::VectorXd randomWeights() {
    std::uniform_real_distribution<double> u(0.2, 2.0);
    Eigen::VectorXd w(13);
    for (Eigen::Index d = 0; d < w.size(); ++d) w(d) = u(rng);
    return w;
  }
  /// The first of the nearest points among [first, end) by brute force.
  const Point* bruteForce(const Eigen::VectorXd& q, std::size_t first = 0) const {
    const Point* best = nullptr;
    double bestDistance = std::numeric_limits<double>::infinity();
    for (std::size_t i = first; i < points.size(); ++i) {
      const double distance = metric.distance(points[i].q, q);
      if (distance < bestDistance) {
        bestDistance = distance;
        best = &points[i];
      }
    }
    return best;
  }

  std::mt19937_64 rng;
  robot::ConfigurationMetric metric;
  std::deque<Point> points;
  ScanNearestNeighbors<const Point*> nn;
};

TEST(ScanNearestNeighbors, NearestIsTheBruteForceNearest) {
  for (const std::size_t count : {1u, 7u, 64u, 65u, 1000u, 5000u}) {
    Fixture f(count, static_cast<unsigned>(count));
    ASSERT_EQ(f.nn.size(), count);
    for (int i = 0; i < 200; ++i) {
      // Far queries (uniform) and near ones (a stored point, moved a little).
      Point probe{i % 2 == 0
                      ? f.randomPoint()
                      : f.points[static_cast<std::size_t>(i) % count].q + 0.01 * f.randomPoint()};
      const Point* expected = f.bruteForce(probe.q);
      ASSERT_NE(expected, nullptr);
      const Point* found = f.nn.nearest(&probe);
      EXPECT_NEAR(f.metric.distance(found->q, probe.q), f.metric.distance(expected->q, probe.q),
                  1e-12)
          << count << " points, query " << i;
      EXPECT_NEAR(f.nn.nearestDistance(probe.q.data()), f.metric.distance(expected->q, probe.q),
                  1e-12);
    }
  }
}

TEST(ScanNearestNeighbors, TheFirstOfEquallyNearPointsWins) {
  robot::ConfigurationMetric metric(Eigen::VectorXd::Ones(3));
  ScanNearestNeighbors<const Point*> nn(metric);
  std::deque<Point> points;
  for (int i = 0; i < 200; ++i) points.push_back({Eigen::Vector3d(i % 2 == 0 ? 1.0 : -1.0, 0, 0)});
  for (const Point& p : points) nn.add(&p);
  const Point origin{Eigen::Vector3d::Zero()};
  EXPECT_EQ(nn.nearest(&origin), &points[0]);
}

TEST(ScanNearestNeighbors, NearestDistanceFromAnIndexOnLooksOnlyAtLaterPoints) {
  Fixture f(3000, 3);
  for (const std::size_t first : {0u, 1u, 63u, 64u, 100u, 2999u}) {
    const Eigen::VectorXd q = f.randomPoint();
    const Point* expected = f.bruteForce(q, first);
    ASSERT_NE(expected, nullptr);
    EXPECT_NEAR(f.nn.nearestDistance(q.data(), first), f.metric.distance(expected->q, q), 1e-12)
        << first;
  }
  EXPECT_EQ(f.nn.nearestDistance(f.randomPoint().data(), 3000),
            std::numeric_limits<double>::infinity());
}

TEST(ScanNearestNeighbors, NearestKAndNearestRAreSortedAndComplete) {
  Fixture f(500, 4);
  const Point probe{f.randomPoint()};
  std::vector<const Point*> k;
  f.nn.nearestK(&probe, 10, k);
  ASSERT_EQ(k.size(), 10u);
  EXPECT_EQ(k.front(), f.bruteForce(probe.q));
  for (std::size_t i = 1; i < k.size(); ++i)
    EXPECT_LE(f.metric.distance(k[i - 1]->q, probe.q), f.metric.distance(k[i]->q, probe.q));
  const double radius = f.metric.distance(k.back()->q, probe.q);
  std::vector<const Point*> r;
  f.nn.nearestR(&probe, radius, r);
  EXPECT_EQ(r, k);
}

TEST(ScanNearestNeighbors, RemoveKeepsTheOthersInOrder) {
  Fixture f(300, 5);
  EXPECT_TRUE(f.nn.remove(&f.points[0]));
  EXPECT_FALSE(f.nn.remove(&f.points[0]));
  std::vector<const Point*> listed;
  f.nn.list(listed);
  ASSERT_EQ(listed.size(), 299u);
  for (std::size_t i = 0; i < listed.size(); ++i) EXPECT_EQ(listed[i], &f.points[i + 1]);
  const Point probe{f.points[0].q};
  EXPECT_EQ(f.nn.nearest(&probe), f.bruteForce(probe.q, 1));
}

TEST(ScanNearestNeighbors, ClearEmptiesAndTheSetFillsAgain) {
  Fixture f(200, 6);
  f.nn.clear();
  EXPECT_EQ(f.nn.size(), 0u);
  const Point probe{f.randomPoint()};
  EXPECT_THROW(f.nn.nearest(&probe), std::logic_error);
  f.nn.add(&f.points[150]);
  f.nn.add(&f.points[10]);
  EXPECT_EQ(f.nn.nearest(&f.points[11]), &f.points[10]);
}

TEST(ScanNearestNeighbors, ChangedWeightsApplyToTheNextQuery) {
  robot::ConfigurationMetric metric(Eigen::VectorXd::Ones(2));
  ScanNearestNeighbors<const Point*> nn(metric);
  const Point a{Eigen::Vector2d(1.0, 0.0)}, b{Eigen::Vector2d(0.0, 1.5)};
  nn.add(&a);
  nn.add(&b);
  const Point origin{Eigen::Vector2d::Zero()};
  EXPECT_EQ(nn.nearest(&origin), &a);
  metric.setWeights(Eigen::Vector2d(4.0, 1.0));  // a at 2, b at 1.5
  EXPECT_EQ(nn.nearest(&origin), &b);
}

}  // namespace
}  // namespace hfts::planner
