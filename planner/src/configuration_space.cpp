#include "planner/configuration_space.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/invalid_argument.h"

namespace hfts::planner {

namespace ob = ompl::base;

WeightedStateSpace::WeightedStateSpace(const robot::RobotModel& model,
                                       std::shared_ptr<robot::ConfigurationMetric> metric)
    : ob::RealVectorStateSpace(static_cast<unsigned int>(model.numDofs())),
      armDofs_(model.numArmDofs()),
      metric_(metric ? std::move(metric)
                     : std::make_shared<robot::ConfigurationMetric>(model.dofWeights())) {
  if (metric_->weights().size() != model.numDofs())
    throw std::invalid_argument("WeightedStateSpace: the metric has " +
                                std::to_string(metric_->weights().size()) + " weights for " +
                                std::to_string(model.numDofs()) + " DoF");
  ob::RealVectorBounds bounds(static_cast<unsigned int>(model.numDofs()));
  for (int i = 0; i < model.numDofs(); ++i) {
    bounds.setLow(static_cast<unsigned int>(i), model.lowerLimits()(i));
    bounds.setHigh(static_cast<unsigned int>(i), model.upperLimits()(i));
    setDimensionName(static_cast<unsigned int>(i), model.dofNames()[static_cast<std::size_t>(i)]);
  }
  setBounds(bounds);
  setName("hfts_weighted_" + model.name());
}

double WeightedStateSpace::distance(const ob::State* a, const ob::State* b) const {
  using Values = Eigen::Map<const Eigen::VectorXd>;
  const Values x(a->as<StateType>()->values, dimension_);
  const Values y(b->as<StateType>()->values, dimension_);
  return metric_->distance(x, y);
}

double WeightedStateSpace::distance(const Eigen::Ref<const Eigen::VectorXd>& a,
                                    const Eigen::Ref<const Eigen::VectorXd>& b) const {
  return metric_->distance(a, b);
}

double WeightedStateSpace::getMaximumExtent() const {
  double sum = 0.0;
  for (unsigned int i = 0; i < dimension_; ++i) {
    const double d = bounds_.high[i] - bounds_.low[i];
    sum += weights()(i) * d * d;
  }
  return std::sqrt(sum);
}

Eigen::VectorXd WeightedStateSpace::toVector(const ob::State* state) const {
  return Eigen::Map<const Eigen::VectorXd>(state->as<StateType>()->values, dimension_);
}

void WeightedStateSpace::fromVector(const Eigen::VectorXd& q, ob::State* state) const {
  Eigen::Map<Eigen::VectorXd>(state->as<StateType>()->values, dimension_) = q;
}

WeightedStateSpace& weightedSpace(const ob::SpaceInformationPtr& si) {
  auto* space = dynamic_cast<WeightedStateSpace*>(si->getStateSpace().get());
  if (space == nullptr)
    throw std::invalid_argument(
        "the space information's state space is not a WeightedStateSpace "
        "(make it with makeSpaceInformation)");
  return *space;
}

CollisionValidityChecker::CollisionValidityChecker(const ob::SpaceInformationPtr& si,
                                                   robot::CollisionChecker& checker)
    : ob::StateValidityChecker(si), space_(weightedSpace(si)), checker_(checker) {}

bool CollisionValidityChecker::isValid(const ob::State* state) const {
  return !checker_.inCollision(space_.toVector(state));
}

CollisionMotionValidator::CollisionMotionValidator(const ob::SpaceInformationPtr& si,
                                                   robot::CollisionChecker& checker,
                                                   double resolution)
    : ob::MotionValidator(si), space_(weightedSpace(si)), checker_(checker) {
  setResolution(resolution);
}

void CollisionMotionValidator::setResolution(double resolution) {
  if (!(resolution > 0.0) || !std::isfinite(resolution))
    throw InvalidArgument("collision_resolution", "must be > 0");
  resolution_ = resolution;
}

bool CollisionMotionValidator::checkMotion(const ob::State* a, const ob::State* b) const {
  const bool valid = checkMotion(space_.toVector(a), space_.toVector(b), resolution_);
  (valid ? valid_ : invalid_)++;
  return valid;
}

bool CollisionMotionValidator::checkMotion(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                                           double resolution) const {
  return checker_.isMotionValid(a, b, resolution);
}

bool CollisionMotionValidator::checkMotion(const ob::State* a, const ob::State* b,
                                           std::pair<ob::State*, double>& lastValid) const {
  const Eigen::VectorXd from = space_.toVector(a);
  const Eigen::VectorXd to = space_.toVector(b);
  const int steps =
      std::max(1, static_cast<int>(std::ceil(space_.distance(from, to) / resolution_)));
  for (int s = 1; s <= steps; ++s) {
    const double t = static_cast<double>(s) / steps;
    if (!checker_.inCollision(from + (to - from) * t)) continue;
    lastValid.second = static_cast<double>(s - 1) / steps;
    if (lastValid.first != nullptr)
      space_.fromVector(from + (to - from) * lastValid.second, lastValid.first);
    invalid_++;
    return false;
  }
  valid_++;
  return true;
}

ob::SpaceInformationPtr makeSpaceInformation(const robot::RobotModel& model,
                                             robot::CollisionChecker& checker, double resolution) {
  auto space = std::make_shared<WeightedStateSpace>(model, checker.sharedMetric());
  auto si = std::make_shared<ob::SpaceInformation>(space);
  si->setStateValidityChecker(std::make_shared<CollisionValidityChecker>(si, checker));
  si->setMotionValidator(std::make_shared<CollisionMotionValidator>(si, checker, resolution));
  si->setup();
  return si;
}

}  // namespace hfts::planner
