#pragma once
// Fingertip kinematics of the hand alone, in the palm frame: positions,
// pad normals and their derivatives with respect to the hand DoF. Made for
// the hand reachability code (grasp/), which evaluates it millions of times
// (map building) or a few dozen times per query (refinement), so it walks
// only the joints between the palm and each fingertip and never allocates.

#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "robot/robot_model.h"

namespace hfts::robot::hand {

/// The reachability map is defined for hands of kMinFingers to kMaxFingers
/// fingertips (the m-contact HFTS: a parallel-jaw gripper, the paper's
/// three-fingered hand, a four-fingered hand) and up to kMaxDofs DoF.
inline constexpr int kMinFingers = 2;
inline constexpr int kMaxFingers = 4;
inline constexpr int kMaxDofs = 16;

/// One column per finger (m columns; fixed capacity, never allocates).
using Tips = Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxFingers>;
/// Rows 3i..3i+2: derivative of finger i's vector; one column per hand DoF.
using TipJacobian =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3 * kMaxFingers, kMaxDofs>;
using HandVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxDofs, 1>;

/// Fingertip positions and unit pad normals (palm frame) of one hand
/// configuration, optionally with their Jacobians.
struct TipState {
  Tips positions;
  Tips normals;
  TipJacobian d_positions;
  TipJacobian d_normals;

  /// A moving joint as evaluated: its axis (times the mimic multiplier)
  /// and origin in the palm frame. Kept so that the Jacobians can be formed
  /// later, only for the configurations that need them.
  struct JointFrame {
    Eigen::Vector3d axis;
    Eigen::Vector3d origin;
    int dof = 0;
    bool revolute = true;
  };
  JointFrame frames[kMaxFingers][kMaxDofs];
  int moving[kMaxFingers] = {};
};

class HandChains {
 public:
  /// Throws ModelError when the hand has fewer than kMinFingers or more than
  /// kMaxFingers fingertips, has
  /// more than kMaxDofs DoF, or a fingertip link is not below the palm
  /// through hand joints only.
  explicit HandChains(const RobotModel& model);

  int numDofs() const { return static_cast<int>(lower_.size()); }
  int numFingers() const { return static_cast<int>(chains_.size()); }
  const Eigen::VectorXd& lower() const { return lower_; }
  const Eigen::VectorXd& upper() const { return upper_; }
  const std::vector<std::string>& dofNames() const { return dof_names_; }
  const std::vector<std::string>& fingerNames() const { return finger_names_; }

  /// Fills positions and normals for hand configuration q (numDofs()
  /// values, unchecked); the Jacobians too when `withJacobians`.
  void evaluate(const double* q, TipState& state, bool withJacobians) const;
  /// Fills the Jacobians of the configuration `state` was evaluated at.
  void jacobians(TipState& state) const;

 private:
  struct ChainJoint {
    Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
    Joint::Type type = Joint::Type::kFixed;
    int dof = -1;  ///< hand DoF index, -1 when fixed
    double multiplier = 1.0;
    double offset = 0.0;
    bool plain_origin = false;  ///< the origin does not rotate
    int principal_axis = -1;    ///< k when the axis is +-e_k (then axis.sum() is its sign)
  };
  struct Chain {
    std::vector<ChainJoint> joints;  ///< palm first
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    Eigen::Vector3d normal = Eigen::Vector3d::UnitX();
  };

  static ChainJoint chainJoint(const RobotModel& model, const Joint& joint, const Fingertip& tip);
  Chain chainTo(const RobotModel& model, const Fingertip& tip) const;
  void evaluateFinger(const Chain& chain, const double* q, int finger, TipState& state) const;

  std::vector<Chain> chains_;
  Eigen::VectorXd lower_, upper_;
  std::vector<std::string> dof_names_, finger_names_;
};

}  // namespace hfts::robot::hand
