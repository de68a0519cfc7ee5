#include "planner/backward_projection.h"

#include <cmath>
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

}  // namespace hfts::planner
