#pragma once
// How far the robot's geometry can move for a step in joint space: the
// bound that lets a straight segment be proven free from distances at a
// few of its states (conservative advancement, segment_certificate.h,
// docs/collision.md "Certified segments").

#include <Eigen/Core>

#include <vector>

#include "robot/robot_model.h"

namespace hfts::robot {

/// For every link and DoF, how many metres any point of the link's
/// collision shapes can travel per radian (revolute) or metre (prismatic)
/// of the DoF, at any configuration. Built from the kinematic chain: a
/// revolute joint moves a point at most its distance from the joint's axis
/// per radian, and that distance is bounded, whatever the joints between,
/// by the lengths of the chain from the joint to the link plus the reach of
/// the link's shapes from its frame (the triangle inequality). Mimic joints
/// count with their multiplier.
class MotionBound {
 public:
  explicit MotionBound(const RobotModel& model);

  /// Upper bound (m) on the length of the path any point of `link` follows
  /// while the configuration moves along the straight segment from any q to
  /// q + step (numDofs values): sum over DoFs of coefficient * |step|.
  /// Throws std::invalid_argument for an unknown link or a step of the
  /// wrong size (as pair() does).
  double link(int link, const Eigen::VectorXd& step) const;

  /// Upper bound (m) on how much closer any point of link `a` can come to
  /// any point of link `b` over the step: the travel of each relative to
  /// their nearest common ancestor link, added (the joints above it move
  /// both alike).
  double pair(int a, int b, const Eigen::VectorXd& step) const;

 private:
  /// One joint's share of a link's coefficients.
  struct ChainJoint {
    int joint = -1;
    int dof = -1;
    double coefficient = 0.0;  ///< metres per unit of the DoF
  };
  void check(int link, const Eigen::VectorXd& step) const;

  /// Metres per unit of each DoF (rows: links, columns: DoFs); a row of
  /// zeros for a link without shapes or one no DoF moves.
  Eigen::MatrixXd coefficients_;
  std::vector<std::vector<ChainJoint>> chains_;  ///< per link, its joints bottom up
};

}  // namespace hfts::robot
