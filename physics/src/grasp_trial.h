#pragma once
// Private to physics/src: one run of the protocol (settle, close, lift,
// hold, disturb) on one compiled model, and the perturbed copies of a
// model the trials run on.

#include <Eigen/Geometry>

#include <vector>

#include "mujoco_world.h"
#include "physics/perturbations.h"
#include "physics/simulate_grasp.h"
#include "physics/simulate_rest.h"

namespace hfts::physics {

/// What every trial of one grasp shares.
struct TrialPlan {
  const robot::RobotModel* robot = nullptr;
  WorldIndex index;
  Eigen::VectorXd pregrasp, grasp;
  /// Per hand DoF, where its servo target runs to: the joint limit in the
  /// closing direction (pregrasp -> grasp), or the grasp value for a DoF
  /// that does not move between the two.
  Eigen::VectorXd close_limit;
  /// Per hand DoF, how far its servo target may run ahead of the joint
  /// while closing (closeLeads()).
  Eigen::VectorXd close_lead;
  std::vector<Eigen::VectorXd> lift;  ///< full configurations, PalmLine::waypoints
  /// How long the lift takes (s): options.lift_time for options.lift_height
  /// of palm travel, longer in proportion for a longer lift (trialPlan
  /// sets it; the default is the default options' lift of the default
  /// height).
  double lift_time = SimulationOptions{}.lift_time;
  Eigen::Isometry3d object_pose = Eigen::Isometry3d::Identity();
  SimulationOptions options;
  /// A pick and place: after the lift, follow this instead of holding and
  /// disturbing (simulatePickAndPlace).
  const PlaceMotion* place = nullptr;
  RestOptions rest;
};

/// The closing targets' end points (TrialPlan::close_limit).
Eigen::VectorXd closeLimits(const robot::RobotModel& robot, const Eigen::VectorXd& pregrasp,
                            const Eigen::VectorXd& grasp);

/// How far ahead of a hand joint its closing target may run, in units of
/// effort / kp: 2, so that a joint held back at the contact presses with
/// twice its effort before the force limit (its effort exactly with the
/// servo gains halved, the gain_low trial).
inline constexpr double kCloseLead = 2.0;

/// Per hand DoF, kCloseLead x effort / kp (TrialPlan::close_lead).
Eigen::VectorXd closeLeads(const robot::RobotModel& robot);

/// A copy of `nominal` with the perturbation's factors applied (every
/// geom's friction, the object body's mass and inertia, the hand servos'
/// kp and damping) and MuJoCo's derived constants recomputed.
ModelPtr perturbedModel(const mjModel& nominal, const WorldIndex& index, int numArmDofs,
                        const Perturbation& perturbation);

/// Runs the protocol on `model` (docs/physics.md). `motion`, when given,
/// receives samples at plan.options.record_rate.
TrialResult runTrial(const mjModel& model, const TrialPlan& plan, const std::string& name,
                     std::vector<MotionSample>* motion = nullptr);

/// Runs a pick and place on `model` (plan.place set): settle, close, the
/// plan's lift, its carry and descent tracked as the lift is, then the
/// hand opening and retreating as planned, then plan.rest.duration still.
PlaceVerdict runPlaceTrial(const mjModel& model, const TrialPlan& plan,
                           std::vector<MotionSample>* motion = nullptr);

}  // namespace hfts::physics
