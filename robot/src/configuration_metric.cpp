#include "robot/configuration_metric.h"

#include <string>

#include "core/invalid_argument.h"

namespace hfts::robot {
namespace {

void checkWeights(const Eigen::VectorXd& weights) {
  // A zero weight would let motion checks step over that DoF's motion.
  if (!weights.allFinite() || (weights.array() <= 0.0).any())
    throw InvalidArgument("weights", "must be finite and > 0");
}

}  // namespace

ConfigurationMetric::ConfigurationMetric(Eigen::VectorXd weights) : weights_(std::move(weights)) {
  checkWeights(weights_);
}

void ConfigurationMetric::setWeights(const Eigen::VectorXd& weights) {
  if (weights.size() != weights_.size())
    throw InvalidArgument("weights", std::to_string(weights_.size()) + " values expected, got " +
                                         std::to_string(weights.size()));
  checkWeights(weights);
  weights_ = weights;
}

}  // namespace hfts::robot
