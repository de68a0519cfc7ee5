#include "planner/backward_projection.h"

#include <cmath>
#include <optional>
#include <stdexcept>

#include "core/invalid_argument.h"
#include "robot/kinematics.h"

namespace hfts::planner {

BackwardProjection::BackwardProjection(const robot::RobotModel& model,
                                       const Eigen::Isometry3d& robotBase,
                                       const Eigen::Vector3d& targetCentre, double maxDistance)
    : model_(model), targetInBase_(robotBase.inverse() * targetCentre) {
  setMaxDistance(maxDistance);
}

void BackwardProjection::setMaxDistance(double maxDistance) {
  if (!(maxDistance >= 0.0) || !std::isfinite(maxDistance))
    throw InvalidArgument("parameters.d_m", "must be finite and >= 0");
  maxDistance_ = maxDistance;
}

bool BackwardProjection::nearTarget(const Eigen::VectorXd& q) const {
  const robot::LinkPoses poses = robot::forwardKinematics(model_, q);
  const Eigen::Vector3d palm = poses[static_cast<std::size_t>(model_.palmLink())].translation();
  return (palm - targetInBase_).norm() <= maxDistance_;
}

Eigen::VectorXd BackwardProjection::gradient(const Eigen::VectorXd& q) const {
  const int arm = model_.numArmDofs();
  const robot::LinkPoses poses = robot::forwardKinematics(model_, q);
  const Eigen::Vector3d palm = poses[static_cast<std::size_t>(model_.palmLink())].translation();
  Eigen::Vector3d away = palm - targetInBase_;
  Eigen::VectorXd h = Eigen::VectorXd::Zero(q.size());
  if (away.norm() > 1e-9) {
    away.normalize();
    const Eigen::MatrixXd j = jacobian(model_, poses, model_.palmLink(), Eigen::Vector3d::Zero())
                                  .topRows<3>()
                                  .leftCols(arm);
    constexpr double kDamping = 1e-2;  // keeps the step bounded near singularities
    const Eigen::Matrix3d jjt = j * j.transpose() + kDamping * Eigen::Matrix3d::Identity();
    const Eigen::VectorXd armStep = j.transpose() * jjt.ldlt().solve(away);
    if (armStep.norm() > 1e-12) h.head(arm) = armStep.normalized();
  }
  const Eigen::VectorXd open = model_.handOpen() - q.tail(model_.numHandDofs());
  if (open.norm() > 1e-9) h.tail(model_.numHandDofs()) = open.normalized();
  const double norm = h.norm();
  return norm > 0.0 ? Eigen::VectorXd(h / norm) : h;
}

Eigen::VectorXd BackwardProjection::project(const Eigen::VectorXd& from,
                                            const Eigen::VectorXd& to) const {
  const Eigen::VectorXd h = gradient(from);
  const double gh = (to - from).dot(h);
  if (!(gh > 0.0)) return to;
  return from + gh * h;
}

std::optional<Eigen::VectorXd> BackwardProjection::retreatStep(const Eigen::VectorXd& q,
                                                               double length, Retreat way) const {
  const int arm = model_.numArmDofs();
  const robot::LinkPoses poses = robot::forwardKinematics(model_, q);
  const Eigen::Vector3d palm = poses[static_cast<std::size_t>(model_.palmLink())].translation();
  Eigen::Vector3d direction = palm - targetInBase_;
  switch (way) {
    case Retreat::kAwayFromTarget:
      break;
    case Retreat::kLevelAway:
      direction.z() = 0.0;
      break;
    case Retreat::kTowardsBase:
      direction = Eigen::Vector3d(-palm.x(), -palm.y(), 0.0);
      break;
    case Retreat::kUp:
      direction = Eigen::Vector3d::UnitZ();
      break;
  }
  if (direction.norm() < 1e-9) return std::nullopt;
  Eigen::Matrix<double, 6, 1> twist;
  twist << direction.normalized() * length, Eigen::Vector3d::Zero();
  const Eigen::MatrixXd j =
      jacobian(model_, poses, model_.palmLink(), Eigen::Vector3d::Zero()).leftCols(arm);
  constexpr double kDamping = 1e-4;  // bounded steps near singularities, exact elsewhere
  const Eigen::Matrix<double, 6, 6> jjt =
      j * j.transpose() + kDamping * Eigen::Matrix<double, 6, 6>::Identity();
  Eigen::VectorXd next = q;
  next.head(arm) += j.transpose() * jjt.ldlt().solve(twist);
  return next;
}

}  // namespace hfts::planner
