#pragma once
// Can the hand carry the object? Epsilon (grasp_quality.h) rates a grasp
// with unit contact forces and knows neither the object's weight nor what
// the hand's joints can push. The load capacity asks what the physics check
// (docs/physics.md) asks of a grasp, quasi-statically: do forces exist at
// the fingertip contacts, inside their friction cones and within the hand
// DoFs' effort limits, that hold the object's weight, and the weight plus a
// disturbance of the same size along each of +-x, +-y, +-z? Its answer is
// the largest factor by which every one of those seven loads can be scaled
// and still be held. Below 1 the grasp cannot hold whatever the servos do;
// above 1 it may (the servos do not choose the best forces; the object may
// roll or slip while the hand closes and lifts).

#include <Eigen/Core>

#include <array>
#include <vector>

#include "grasp/hand_closing.h"
#include "robot/object_surface.h"
#include "robot/robot_model.h"

namespace hfts::grasp {

/// One load case per entry: the weight alone, then with an equal force
/// along +x, -x, +y, -y, +z, -z (the physics check's disturbances).
inline constexpr int kLoadCases = 7;

struct LoadCapacityRequest {
  /// Contact points and inward unit normals, one column per fingertip, in
  /// the frame of `down` (the world).
  Eigen::Matrix3Xd positions;
  Eigen::Matrix3Xd normals;
  /// Per contact: the 6 x numHandDofs Jacobian of its fingertip link at the
  /// contact point (linear velocity of the point on top, angular velocity
  /// below) with respect to the hand's DoF, in the same frame. A contact
  /// force f with a moment m about the normal needs the DoF forces
  /// J^T [f; m].
  std::vector<Eigen::MatrixXd> jacobians;
  Eigen::VectorXd efforts;  ///< the largest force or torque of each hand DoF (> 0)
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< the object's centre of mass
  double weight = 0.0;                               ///< m g (N), > 0
  Eigen::Vector3d down = -Eigen::Vector3d::UnitZ();  ///< gravity's direction (unit)
  double friction = 0.5;                             ///< mu > 0
  double torsional_friction = 0.0;                   ///< gamma (m) of soft fingers, >= 0
  int cone_edges = 8;                                ///< K >= 3
};

struct LoadCapacity {
  /// The smallest of per_case: every load case scaled by it is held.
  double factor = 0.0;
  /// Per load case (kLoadCases, in the order above), the largest scale of
  /// that load the contacts can hold; kUnbounded when the load is zero
  /// (the weight cancelled by an upward push) or the structure alone
  /// carries it.
  std::array<double, kLoadCases> per_case{};
};

/// The cap of LoadCapacity's factors (a load no effort limit bounds).
inline constexpr double kUnboundedLoad = 100.0;

/// Solves one linear program per load case over the contacts' friction
/// cones (the primitive wrenches of contactWrenches, so soft fingers resist
/// a torque about their normal as in epsilon), each pyramid around its
/// cone (mu / cos(pi / K) at the edges): the capacity is an upper bound. Throws InvalidArgument
/// naming the field for mismatched sizes, no contacts, non-finite values or
/// parameters out of range.
LoadCapacity loadCapacity(const LoadCapacityRequest& request);

/// The request for a robot whose hand closed on an object: contacts in the
/// world with the DoF Jacobians of the fingertips touching them at the
/// full configuration q (robot base at `base` in the world, the object at
/// `object_pose`), the robot config's hand efforts (hand_actuation) and
/// soft-finger gamma, the object's centre of mass (object frame) and mass.
/// With the object's `surface`, a pad that lies on it touches along a
/// patch, as a rigid pad pressed on a face does: the corners of the
/// surface points within 0.5 mm of the fingertip link near the contact
/// (a grid over 1.5 pad radii) are its contacts, so the patch resists
/// twisting and tilting; without it, or where the patch is a point, one
/// contact per finger. Throws InvalidArgument when the robot has no
/// hand_actuation or the hand does not touch with every pad.
LoadCapacityRequest loadRequest(const robot::RobotModel& robot, const Eigen::VectorXd& q,
                                const Eigen::Isometry3d& base, const HandClosure& closure,
                                const Eigen::Isometry3d& object_pose,
                                const Eigen::Vector3d& center_of_mass, double mass,
                                const robot::ObjectSurface* surface = nullptr);

}  // namespace hfts::grasp
