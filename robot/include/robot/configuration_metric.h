#pragma once
// The distance between robot configurations of the paper's Eq. (3). One
// object serves every user of the metric in a plan: the collision checker
// (motion checks at a resolution), the OMPL state space (trees, nearest
// neighbours) and the goal sampler's ratings, so changing a weight changes
// it for all of them.

#include <Eigen/Core>

#include <cmath>

namespace hfts::robot {

/// sqrt(sum_i w_i (a_i - b_i)^2) over the robot's DoF.
class ConfigurationMetric {
 public:
  /// Throws InvalidArgument ("weights") unless every weight is finite and
  /// > 0 (a zero weight would let motion checks step over that DoF).
  explicit ConfigurationMetric(Eigen::VectorXd weights);

  double distance(const Eigen::Ref<const Eigen::VectorXd>& a,
                  const Eigen::Ref<const Eigen::VectorXd>& b) const {
    return std::sqrt((weights_.array() * (a - b).array().square()).sum());
  }

  const Eigen::VectorXd& weights() const { return weights_; }
  /// Throws InvalidArgument ("weights") for another number of weights or a
  /// weight that is not finite and > 0.
  void setWeights(const Eigen::VectorXd& weights);

 private:
  Eigen::VectorXd weights_;
};

}  // namespace hfts::robot
