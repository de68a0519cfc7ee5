#include "robot/configuration_metric.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/invalid_argument.h"

namespace hfts::robot {
namespace {

TEST(ConfigurationMetric, IsTheWeightedNormOfEquation3) {
  const ConfigurationMetric metric(Eigen::Vector3d(1.0, 0.25, 0.01));
  const Eigen::Vector3d a(0.0, 1.0, 5.0), b(3.0, -1.0, -5.0);
  // sqrt(1 * 9 + 0.25 * 4 + 0.01 * 100)
  EXPECT_DOUBLE_EQ(metric.distance(a, b), std::sqrt(11.0));
  EXPECT_DOUBLE_EQ(metric.distance(b, a), metric.distance(a, b));
  EXPECT_EQ(metric.distance(a, a), 0.0);
}

TEST(ConfigurationMetric, NewWeightsApplyToEveryLaterDistance) {
  ConfigurationMetric metric(Eigen::Vector2d(1.0, 1.0));
  const Eigen::Vector2d a(0.0, 0.0), b(1.0, 2.0);
  EXPECT_DOUBLE_EQ(metric.distance(a, b), std::sqrt(5.0));
  metric.setWeights(Eigen::Vector2d(4.0, 0.25));
  EXPECT_DOUBLE_EQ(metric.distance(a, b), std::sqrt(5.0));
  EXPECT_EQ(metric.weights(), Eigen::Vector2d(4.0, 0.25));
}

TEST(ConfigurationMetric, RejectsBadWeightsNamingThem) {
  EXPECT_THROW(ConfigurationMetric(Eigen::Vector2d(1.0, -0.1)), InvalidArgument);
  EXPECT_THROW(ConfigurationMetric(Eigen::Vector2d(1.0, 0.0)), InvalidArgument);
  EXPECT_THROW(ConfigurationMetric(Eigen::Vector2d(1.0, NAN)), InvalidArgument);
  ConfigurationMetric metric(Eigen::Vector2d(1.0, 1.0));
  try {
    metric.setWeights(Eigen::Vector3d(1.0, 1.0, 1.0));
    FAIL() << "three weights for two DoF were accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.field(), "weights");
    EXPECT_STREQ(e.what(), "weights: 2 values expected, got 3");
  }
  EXPECT_EQ(metric.weights(), Eigen::Vector2d(1.0, 1.0));  // unchanged
}

}  // namespace
}  // namespace hfts::robot
