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

#include "planner/collision_checker.h"

namespace hfts::planner {

class WeightedStateSpace : public ompl::base::RealVectorStateSpace {
 public:
  /// Bounds are the joint limits, weights the robot's DoF weights.
  explicit WeightedStateSpace(const RobotModel& model);

  /// Eq. (3): sqrt(sum_i w_i (a_i - b_i)^2).
  double distance(const ompl::base::State* a, const ompl::base::State* b) const override;
  double distance(const Eigen::Ref<const Eigen::VectorXd>& a,
                  const Eigen::Ref<const Eigen::VectorXd>& b) const;
  double getMaximumExtent() const override;

  int armDofs() const { return armDofs_; }
  const Eigen::VectorXd& weights() const { return weights_; }
  /// Throws std::invalid_argument for a wrong size or a negative weight.
  void setWeights(const Eigen::VectorXd& weights);

  Eigen::VectorXd toVector(const ompl::base::State* state) const;
  void fromVector(const Eigen::VectorXd& q, ompl::base::State* state) const;

 private:
  int armDofs_ = 0;
  Eigen::VectorXd weights_;
};

/// Valid = no collision under the full rule (obstacles, target, self).
class CollisionValidityChecker : public ompl::base::StateValidityChecker {
 public:
  CollisionValidityChecker(const ompl::base::SpaceInformationPtr& si, CollisionChecker& checker);
  bool isValid(const ompl::base::State* state) const override;

 private:
  const WeightedStateSpace& space_;
  CollisionChecker& checker_;
};

/// Straight-line motions checked at a fixed resolution in the Eq. (3)
/// metric (every intermediate state and the end state).
class CollisionMotionValidator : public ompl::base::MotionValidator {
 public:
  CollisionMotionValidator(const ompl::base::SpaceInformationPtr& si, CollisionChecker& checker,
                           double resolution);
  bool checkMotion(const ompl::base::State* a, const ompl::base::State* b) const override;
  bool checkMotion(const ompl::base::State* a, const ompl::base::State* b,
                   std::pair<ompl::base::State*, double>& lastValid) const override;
  /// The same check at another resolution (the planner's final re-check).
  bool checkMotion(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double resolution) const;

  CollisionChecker& checker() const { return checker_; }
  /// A single configuration under the full rule.
  bool isValid(const Eigen::VectorXd& q) const { return !checker_.inCollision(q); }

  double resolution() const { return resolution_; }
  /// Throws std::invalid_argument unless resolution > 0.
  void setResolution(double resolution);

 private:
  const WeightedStateSpace& space_;
  CollisionChecker& checker_;
  double resolution_;
};

/// Space, validity checker and motion validator, set up. The space's
/// weights start as the checker's (they must stay equal: the planner's
/// weight parameters set both).
ompl::base::SpaceInformationPtr makeSpaceInformation(const RobotModel& model,
                                                     CollisionChecker& checker, double resolution);

}  // namespace hfts::planner
