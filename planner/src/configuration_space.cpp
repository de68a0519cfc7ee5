#include "planner/configuration_space.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hfts::planner {

namespace ob = ompl::base;

WeightedStateSpace::WeightedStateSpace(const RobotModel& model)
    : ob::RealVectorStateSpace(static_cast<unsigned int>(model.numDofs())),
      armDofs_(model.numArmDofs()) {
  ob::RealVectorBounds bounds(static_cast<unsigned int>(model.numDofs()));
  for (int i = 0; i < model.numDofs(); ++i) {
    bounds.setLow(static_cast<unsigned int>(i), model.lowerLimits()(i));
    bounds.setHigh(static_cast<unsigned int>(i), model.upperLimits()(i));
    setDimensionName(static_cast<unsigned int>(i), model.dofNames()[static_cast<std::size_t>(i)]);
  }
  setBounds(bounds);
  setName("hfts_weighted_" + model.name());
  setWeights(model.dofWeights());
}

void WeightedStateSpace::setWeights(const Eigen::VectorXd& weights) {
  if (weights.size() != static_cast<Eigen::Index>(getDimension()))
    throw std::invalid_argument("state space: " + std::to_string(getDimension()) +
                                " weights expected, got " + std::to_string(weights.size()));
  if ((weights.array() < 0.0).any() || !weights.allFinite())
    throw std::invalid_argument("state space: weights must be finite and >= 0");
  weights_ = weights;
}

double WeightedStateSpace::distance(const ob::State* a, const ob::State* b) const {
  using Values = Eigen::Map<const Eigen::VectorXd>;
  const Values x(a->as<StateType>()->values, dimension_);
  const Values y(b->as<StateType>()->values, dimension_);
  return std::sqrt((weights_.array() * (x - y).array().square()).sum());
}

double WeightedStateSpace::distance(const Eigen::Ref<const Eigen::VectorXd>& a,
                                    const Eigen::Ref<const Eigen::VectorXd>& b) const {
  return std::sqrt((weights_.array() * (a - b).array().square()).sum());
}

double WeightedStateSpace::getMaximumExtent() const {
  double sum = 0.0;
  for (unsigned int i = 0; i < dimension_; ++i) {
    const double d = bounds_.high[i] - bounds_.low[i];
    sum += weights_(i) * d * d;
  }
  return std::sqrt(sum);
}

Eigen::VectorXd WeightedStateSpace::toVector(const ob::State* state) const {
  return Eigen::Map<const Eigen::VectorXd>(state->as<StateType>()->values, dimension_);
}

void WeightedStateSpace::fromVector(const Eigen::VectorXd& q, ob::State* state) const {
  Eigen::Map<Eigen::VectorXd>(state->as<StateType>()->values, dimension_) = q;
}

namespace {
const WeightedStateSpace& weightedSpace(const ob::SpaceInformationPtr& si) {
  const auto* space = dynamic_cast<const WeightedStateSpace*>(si->getStateSpace().get());
  if (space == nullptr) throw std::invalid_argument("expected a WeightedStateSpace");
  return *space;
}
}  // namespace

CollisionValidityChecker::CollisionValidityChecker(const ob::SpaceInformationPtr& si,
                                                   CollisionChecker& checker)
    : ob::StateValidityChecker(si), space_(weightedSpace(si)), checker_(checker) {}

bool CollisionValidityChecker::isValid(const ob::State* state) const {
  return !checker_.inCollision(space_.toVector(state));
}

CollisionMotionValidator::CollisionMotionValidator(const ob::SpaceInformationPtr& si,
                                                   CollisionChecker& checker, double resolution)
    : ob::MotionValidator(si), space_(weightedSpace(si)), checker_(checker) {
  setResolution(resolution);
}

void CollisionMotionValidator::setResolution(double resolution) {
  if (!(resolution > 0.0) || !std::isfinite(resolution))
    throw std::invalid_argument("collision resolution must be > 0");
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
      std::max(1, static_cast<int>(std::ceil(checker_.distance(from, to) / resolution_)));
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

ob::SpaceInformationPtr makeSpaceInformation(const RobotModel& model, CollisionChecker& checker,
                                             double resolution) {
  auto space = std::make_shared<WeightedStateSpace>(model);
  space->setWeights(checker.dofWeights());
  auto si = std::make_shared<ob::SpaceInformation>(space);
  si->setStateValidityChecker(std::make_shared<CollisionValidityChecker>(si, checker));
  si->setMotionValidator(std::make_shared<CollisionMotionValidator>(si, checker, resolution));
  si->setup();
  return si;
}

}  // namespace hfts::planner
