#include "robot/hand_chain.h"

#include <algorithm>
#include <cmath>

namespace hfts::robot::hand {

HandChains::HandChains(const RobotModel& model) {
  const int arm = model.numArmDofs();
  const int dofs = model.numHandDofs();
  if (dofs < 1 || dofs > kMaxDofs)
    throw ModelError(model.name() + ": the hand has " + std::to_string(dofs) +
                     " DoF; the reachability map supports 1 to " + std::to_string(kMaxDofs));
  const auto fingers = static_cast<int>(model.fingertips().size());
  if (fingers < kMinFingers || fingers > kMaxFingers)
    throw ModelError(model.name() + ": the hand has " + std::to_string(fingers) +
                     " fingertips; the reachability map supports " + std::to_string(kMinFingers) +
                     " to " + std::to_string(kMaxFingers));
  lower_ = model.lowerLimits().tail(dofs);
  upper_ = model.upperLimits().tail(dofs);
  dof_names_.assign(model.dofNames().begin() + arm, model.dofNames().end());
  for (const Fingertip& tip : model.fingertips()) {
    chains_.push_back(chainTo(model, tip));
    finger_names_.push_back(tip.name);
  }
}

HandChains::ChainJoint HandChains::chainJoint(const RobotModel& model, const Joint& joint,
                                              const Fingertip& tip) {
  ChainJoint c{joint.origin, joint.axis, joint.type, -1, joint.multiplier, joint.offset};
  c.plain_origin = joint.origin.linear().isIdentity(0.0);
  for (int k = 0; k < 3; ++k)
    if (std::abs(std::abs(c.axis(k)) - 1.0) < 1e-15 && c.axis.norm() < 1.0 + 1e-15)
      c.principal_axis = k;
  if (joint.type == Joint::Type::kFixed) return c;
  c.dof = joint.dof - model.numArmDofs();
  if (c.dof < 0)
    throw ModelError(model.name() + ": joint '" + joint.name + "' between the palm and '" +
                     tip.name + "' is driven by an arm DoF");
  return c;
}

HandChains::Chain HandChains::chainTo(const RobotModel& model, const Fingertip& tip) const {
  Chain chain;
  chain.point = tip.point;
  chain.normal = tip.normal.normalized();
  for (int link = tip.link; link != model.palmLink();) {
    const int j = model.links()[static_cast<std::size_t>(link)].parent_joint;
    if (j < 0)
      throw ModelError(model.name() + ": fingertip '" + tip.name + "' is not below the palm");
    const Joint& joint = model.joints()[static_cast<std::size_t>(j)];
    chain.joints.push_back(chainJoint(model, joint, tip));
    link = joint.parent_link;
  }
  std::reverse(chain.joints.begin(), chain.joints.end());
  const auto moving = std::count_if(chain.joints.begin(), chain.joints.end(),
                                    [](const ChainJoint& j) { return j.dof >= 0; });
  if (moving > kMaxDofs)
    throw ModelError(model.name() + ": more than " + std::to_string(kMaxDofs) +
                     " moving joints between the palm and '" + tip.name + "'");
  return chain;
}

void HandChains::evaluate(const double* q, TipState& state, bool withJacobians) const {
  state.positions.resize(3, numFingers());
  state.normals.resize(3, numFingers());
  for (int f = 0; f < numFingers(); ++f)
    evaluateFinger(chains_[static_cast<std::size_t>(f)], q, f, state);
  if (withJacobians) jacobians(state);
}

void HandChains::jacobians(TipState& state) const {
  state.d_positions.setZero(3 * numFingers(), numDofs());
  state.d_normals.setZero(3 * numFingers(), numDofs());
  for (int f = 0; f < numFingers(); ++f) {
    const Eigen::Vector3d p = state.positions.col(f), n = state.normals.col(f);
    for (int k = 0; k < state.moving[f]; ++k) {
      const TipState::JointFrame& joint = state.frames[f][k];
      auto dp = state.d_positions.block<3, 1>(3 * f, joint.dof);
      auto dn = state.d_normals.block<3, 1>(3 * f, joint.dof);
      if (joint.revolute) {
        dp += joint.axis.cross(p - joint.origin);
        dn += joint.axis.cross(n);
      } else {
        dp += joint.axis;
      }
    }
  }
}

namespace {

/// rotation * (rotation by `angle` about principal axis `k`), touching only
/// the two columns that change: the common case of URDF hands.
void turnAboutPrincipalAxis(Eigen::Matrix3d& rotation, int k, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  const int a = (k + 1) % 3, b = (k + 2) % 3;
  const Eigen::Vector3d ca = rotation.col(a), cb = rotation.col(b);
  rotation.col(a) = c * ca + s * cb;
  rotation.col(b) = c * cb - s * ca;
}

}  // namespace

void HandChains::evaluateFinger(const Chain& chain, const double* q, int finger,
                                TipState& state) const {
  TipState::JointFrame* frames = state.frames[finger];
  int moving = 0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  for (const ChainJoint& joint : chain.joints) {
    position += rotation * joint.origin.translation();
    if (!joint.plain_origin) rotation = rotation * joint.origin.linear();
    if (joint.type == Joint::Type::kFixed) continue;
    const double value = joint.multiplier * q[joint.dof] + joint.offset;
    const Eigen::Vector3d axis = rotation * joint.axis;
    // At most kMaxDofs moving joints per chain (checked in chainTo).
    frames[moving++] = {joint.multiplier * axis, position, joint.dof,
                        joint.type == Joint::Type::kRevolute};
    if (joint.type == Joint::Type::kPrismatic)
      position += value * axis;
    else if (joint.principal_axis >= 0)
      turnAboutPrincipalAxis(rotation, joint.principal_axis, joint.axis.sum() * value);
    else
      rotation = rotation * Eigen::AngleAxisd(value, joint.axis).toRotationMatrix();
  }
  state.moving[finger] = moving;
  state.positions.col(finger) = position + rotation * chain.point;
  state.normals.col(finger) = rotation * chain.normal;
}

}  // namespace hfts::robot::hand
