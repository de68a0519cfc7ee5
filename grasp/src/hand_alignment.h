#pragma once
// Putting the fingertips onto their contacts (m = 2..4 of them): the best palm pose for a
// fixed hand posture (weighted Kabsch, closed form) and the local
// refinement of posture and pose together (Levenberg-Marquardt). Private to
// the hand reachability code; the residual is the one defined in
// grasp/hand_reachability.h.

#include "grasp/hand_reachability.h"
#include "robot/hand_chain.h"

namespace hfts::grasp::hand {

using robot::hand::HandChains;
using robot::hand::HandVector;
using robot::hand::kMaxDofs;
using robot::hand::Tips;
using robot::hand::TipState;

/// Contacts in finger order (one column per finger): column f is the contact finger f must
/// reach and the direction its pad must face (the inward contact normal).
struct Target {
  Tips contacts;
  Tips pad_normals;
  double lambda = 0.0;  ///< weight (m) of a unit normal error
};

/// A palm pose, target <- palm, and its cost: the sum over the fingers of
/// |R f + t - c|^2 + lambda^2 |R a - b|^2 (so R(h) = sqrt(cost / m)).
struct Alignment {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double cost = 0.0;
};

/// The smallest cost over palm poses, without forming the pose: from the
/// singular values of the weighted cross-covariance (about 0.1 us).
double alignmentCost(const Tips& positions, const Tips& normals, const Target& target);

/// The palm pose of smallest cost (positions with weight 1, pad normals as
/// directions with weight lambda^2; proper rotations only).
Alignment align(const Tips& positions, const Tips& normals, const Target& target);

/// The same cost for a given pose.
double costOf(const Tips& positions, const Tips& normals, const Target& target,
              const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation);

/// A hand posture and the palm pose reaching the target.
struct Solution {
  HandVector q;
  Alignment pose;
};

/// Levenberg-Marquardt on the hand DoF and the palm rotation together (the
/// translation follows in closed form), from a grasp posture q0 and its
/// best palm pose. Steps are clamped to the joint
/// limits and accepted only when they lower the cost and keep a grasp
/// posture (isGraspPosture), so the result is never worse than q0 and
/// stays in the set the map samples. Resumable, so that a query can probe
/// several starts cheaply and finish only the most promising one.
class Refinement {
 public:
  Refinement(const HandChains& chains, const HandMapOptions& posture, const Target& target,
             const HandVector& q0);

  /// Up to `iterations` more iterations; stops early once the cost is ~0
  /// or no longer falls by a useful fraction.
  void iterate(int iterations);
  /// Continuation: moves the target from where the fingertips are now to
  /// the real one in `stages` steps, iterating at each, so the solution is
  /// tracked instead of jumping into another basin.
  void track(int stages, int iterationsPerStage);
  bool finished() const { return finished_; }
  double cost() const { return best_.pose.cost; }
  const Solution& solution() const { return best_; }
  /// Fingertips of solution().q, palm frame.
  const TipState& tips() const { return states_[current_]; }

 private:
  bool step();
  void retarget();

  const HandChains* chains_;
  const HandMapOptions* posture_;
  Target target_;
  Solution best_;
  /// The state at best_.q (with Jacobians) and the trial's, swapped by index
  /// on acceptance instead of copied.
  TipState states_[2];
  int current_ = 0;
  double mu_ = 1e-3;
  bool finished_ = false;
};

}  // namespace hfts::grasp::hand
