#pragma once
// The free-space knowledge a hierarchical goal sampler rates with (paper
// Sec. III), internal to the planner library: the planner's trees plus the
// sampler's approximate-goal set A.

#include <Eigen/Core>

#include <algorithm>
#include <vector>

#include "planner/goal_hierarchy_cache.h"
#include "robot/configuration_metric.h"

namespace hfts::planner {

/// The planner's knowledge plus the approximate-goal set A, which belongs
/// to the non-connected free space too (paper Sec. III).
class WithApproximateGoals : public FreeSpaceDistances {
 public:
  WithApproximateGoals(const FreeSpaceDistances& planner, const std::vector<Eigen::VectorXd>& goals,
                       const robot::ConfigurationMetric& metric)
      : planner_(planner), goals_(goals), metric_(metric) {}
  double toNonConnected(const Eigen::VectorXd& q) const override {
    return orApproximateGoal(planner_.toNonConnected(q), q);
  }
  double toConnected(const Eigen::VectorXd& q) const override { return planner_.toConnected(q); }
  FreeSpaceDistance distances(const Eigen::VectorXd& q, FreeSpaceMemo& memo) const override {
    // The memo is the planner's; A changes both ways and is small.
    FreeSpaceDistance d = planner_.distances(q, memo);
    d.to_non_connected = orApproximateGoal(d.to_non_connected, q);
    return d;
  }

 private:
  double orApproximateGoal(double d, const Eigen::VectorXd& q) const {
    for (const Eigen::VectorXd& a : goals_) d = std::min(d, metric_.distance(q, a));
    return d;
  }

  const FreeSpaceDistances& planner_;
  const std::vector<Eigen::VectorXd>& goals_;
  const robot::ConfigurationMetric& metric_;
};

}  // namespace hfts::planner
