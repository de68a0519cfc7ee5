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
    return distance(a.data(), b.data());
  }

  /// The same of two arrays of weights().size() values: the form nearest
  /// neighbour searches call millions of times in a plan.
  double distance(const double* a, const double* b) const {
    const double* w = weights_.data();
    const Eigen::Index n = weights_.size();
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    Eigen::Index i = 0;
    for (; i + 4 <= n; i += 4) {
      const double d0 = a[i] - b[i], d1 = a[i + 1] - b[i + 1], d2 = a[i + 2] - b[i + 2],
                   d3 = a[i + 3] - b[i + 3];
      s0 += w[i] * d0 * d0;
      s1 += w[i + 1] * d1 * d1;
      s2 += w[i + 2] * d2 * d2;
      s3 += w[i + 3] * d3 * d3;
    }
    for (; i < n; ++i) s0 += w[i] * (a[i] - b[i]) * (a[i] - b[i]);
    return std::sqrt((s0 + s1) + (s2 + s3));
  }

  const Eigen::VectorXd& weights() const { return weights_; }
  /// Throws InvalidArgument ("weights") for another number of weights or a
  /// weight that is not finite and > 0.
  void setWeights(const Eigen::VectorXd& weights);

 private:
  Eigen::VectorXd weights_;
};

}  // namespace hfts::robot
