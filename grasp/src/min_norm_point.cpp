#include "min_norm_point.h"

#include <Eigen/QR>

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace hfts::grasp {
namespace {

/// The point of the affine hull of the chosen columns nearest to the
/// origin, as affine weights (summing to 1).
Eigen::VectorXd affineMinimum(const Eigen::MatrixXd& points, const std::vector<Eigen::Index>& set) {
  const auto k = static_cast<Eigen::Index>(set.size());
  Eigen::MatrixXd system = Eigen::MatrixXd::Zero(k + 1, k + 1);
  for (Eigen::Index i = 0; i < k; ++i) {
    for (Eigen::Index j = 0; j < k; ++j)
      system(i, j) = points.col(set[static_cast<std::size_t>(i)])
                         .dot(points.col(set[static_cast<std::size_t>(j)]));
    system(i, k) = 1.0;
    system(k, i) = 1.0;
  }
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(k + 1);
  rhs(k) = 1.0;
  // Affinely dependent corrals make the system singular: the minimum-norm
  // solution still gives valid affine weights.
  return system.completeOrthogonalDecomposition().solve(rhs).head(k);
}

}  // namespace

double distanceToHull(const Eigen::MatrixXd& points) {
  if (points.cols() == 0) throw std::invalid_argument("distanceToHull: no points");
  const double scale = points.colwise().squaredNorm().maxCoeff();
  const double tolerance = 1e-12 * std::max(scale, 1e-300);
  Eigen::Index start = 0;
  points.colwise().squaredNorm().minCoeff(&start);
  std::vector<Eigen::Index> set{start};  // the corral
  std::vector<double> weights{1.0};
  Eigen::VectorXd x = points.col(start);
  const auto pointOf = [&] {
    Eigen::VectorXd p = Eigen::VectorXd::Zero(points.rows());
    for (std::size_t i = 0; i < set.size(); ++i) p += weights[i] * points.col(set[i]);
    return p;
  };
  for (int major = 0; major < 100000; ++major) {
    if (x.squaredNorm() <= tolerance) return 0.0;
    Eigen::Index j = 0;
    const double best = (points.transpose() * x).minCoeff(&j);
    if (best >= x.squaredNorm() - tolerance) return x.norm();                // x separates: optimal
    if (std::find(set.begin(), set.end(), j) != set.end()) return x.norm();  // no progress left
    set.push_back(j);
    weights.push_back(0.0);
    for (int minor = 0; minor < 1000; ++minor) {
      const Eigen::VectorXd mu = affineMinimum(points, set);
      if ((mu.array() > 1e-15).all()) {
        for (std::size_t i = 0; i < set.size(); ++i) weights[i] = mu(static_cast<Eigen::Index>(i));
        break;
      }
      // Step from the current weights towards mu until one weight reaches 0.
      double theta = 1.0;
      for (std::size_t i = 0; i < set.size(); ++i) {
        const double m = mu(static_cast<Eigen::Index>(i));
        if (m <= 1e-15 && weights[i] - m > 0.0)
          theta = std::min(theta, weights[i] / (weights[i] - m));
      }
      for (std::size_t i = 0; i < set.size(); ++i)
        weights[i] = (1.0 - theta) * weights[i] + theta * mu(static_cast<Eigen::Index>(i));
      for (std::size_t i = set.size(); i-- > 0;)
        if (weights[i] <= 1e-15) {
          set.erase(set.begin() + static_cast<std::ptrdiff_t>(i));
          weights.erase(weights.begin() + static_cast<std::ptrdiff_t>(i));
        }
      if (set.empty()) throw std::logic_error("distanceToHull: the corral emptied");
    }
    double sum = 0.0;
    for (const double w : weights) sum += w;
    for (double& w : weights) w /= sum;
    x = pointOf();
  }
  return x.norm();
}

}  // namespace hfts::grasp
