#pragma once
// The robot's configuration space as OMPL sees it: a RealVectorStateSpace
// whose distance is the weighted norm of the paper's Eq. (3) (OMPL's
// compound spaces would sum per-joint distances instead), with validity and
// motion checks from our CollisionChecker. Include only where OMPL is used.

#include <ompl/base/MotionValidator.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/StateValidityChecker.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>

#include <Eigen/Core>

#include <memory>

#include "robot/collision_checker.h"

namespace hfts::planner {

class WeightedStateSpace : public ompl::base::RealVectorStateSpace {
 public:
  /// Bounds are the joint limits. The distance is `metric`'s (shared, e.g.
  /// with a collision checker), or when null a metric of the robot's own.
  explicit WeightedStateSpace(const robot::RobotModel& model,
                              std::shared_ptr<robot::ConfigurationMetric> metric = nullptr);

  /// Eq. (3): sqrt(sum_i w_i (a_i - b_i)^2).
  double distance(const ompl::base::State* a, const ompl::base::State* b) const override;
  double distance(const Eigen::Ref<const Eigen::VectorXd>& a,
                  const Eigen::Ref<const Eigen::VectorXd>& b) const;
  double getMaximumExtent() const override;
  /// None: no planner of the project projects states, and OMPL's default
  /// projection samples states to size its cells at every set-up (3 % of
  /// a MotionBenchMaker plan's time under perf; a planner that needs one
  /// gets OMPL's "no default projection" error).
  void registerProjections() override {}

  int armDofs() const { return armDofs_; }
  const robot::ConfigurationMetric& metric() const { return *metric_; }
  const Eigen::VectorXd& weights() const { return metric_->weights(); }
  /// Sets the shared metric's weights. Throws InvalidArgument ("weights")
  /// for a wrong size or a negative weight.
  void setWeights(const Eigen::VectorXd& weights) { metric_->setWeights(weights); }

  Eigen::VectorXd toVector(const ompl::base::State* state) const;
  void fromVector(const Eigen::VectorXd& q, ompl::base::State* state) const;

 private:
  int armDofs_ = 0;
  std::shared_ptr<robot::ConfigurationMetric> metric_;
};

/// The space of `si` as a WeightedStateSpace. Throws std::invalid_argument
/// when `si` was not made by makeSpaceInformation() (another state space).
WeightedStateSpace& weightedSpace(const ompl::base::SpaceInformationPtr& si);

/// Valid = no collision under the full rule (obstacles, target, self).
class CollisionValidityChecker : public ompl::base::StateValidityChecker {
 public:
  CollisionValidityChecker(const ompl::base::SpaceInformationPtr& si,
                           robot::CollisionChecker& checker);
  bool isValid(const ompl::base::State* state) const override;

 private:
  const WeightedStateSpace& space_;
  robot::CollisionChecker& checker_;
};

/// Straight-line motions checked at a fixed resolution in the Eq. (3)
/// metric (every intermediate state and the end state).
class CollisionMotionValidator : public ompl::base::MotionValidator {
 public:
  CollisionMotionValidator(const ompl::base::SpaceInformationPtr& si,
                           robot::CollisionChecker& checker, double resolution);
  bool checkMotion(const ompl::base::State* a, const ompl::base::State* b) const override;
  bool checkMotion(const ompl::base::State* a, const ompl::base::State* b,
                   std::pair<ompl::base::State*, double>& lastValid) const override;
  /// The same check at another resolution (the planner's final re-check).
  bool checkMotion(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double resolution) const;
  /// The number of leading steps of the polyline *line[0] -> *line[1] ->
  /// ... (`count` vertices) that checkMotion accepts (line[0] assumed
  /// valid), all checked in one stream (robot::CollisionChecker::validSegments).
  std::size_t validSteps(const Eigen::VectorXd* const* line, std::size_t count) const {
    return checker_.validSegments(line, count, resolution_);
  }

  robot::CollisionChecker& checker() const { return checker_; }
  /// A single configuration under the full rule.
  bool isValid(const Eigen::VectorXd& q) const { return !checker_.inCollision(q); }

  double resolution() const { return resolution_; }
  /// Throws std::invalid_argument unless resolution > 0.
  void setResolution(double resolution);

 private:
  const WeightedStateSpace& space_;
  robot::CollisionChecker& checker_;
  double resolution_;
};

/// Space, validity checker and motion validator, set up. The space's metric
/// is the checker's (one object: the planner's weight parameters set it).
ompl::base::SpaceInformationPtr makeSpaceInformation(const robot::RobotModel& model,
                                                     robot::CollisionChecker& checker,
                                                     double resolution);

}  // namespace hfts::planner
