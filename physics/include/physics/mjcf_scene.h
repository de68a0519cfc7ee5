#pragma once
// The simulated world as MJCF text (MuJoCo's model format), written from
// the loaded RobotModel, the scene and the object's body: we write MJCF
// ourselves instead of letting MuJoCo compile the URDF, because MuJoCo 2.2
// ignores <mimic> and knows nothing of the robot config (fingertips,
// actuation), and this way every geom, contact, actuator and equality
// constraint is ours to set (docs/physics.md).

#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "physics/object_body.h"
#include "robot/robot_model.h"
#include "robot/scene.h"

namespace hfts::physics {

/// The object as a free body.
struct ObjectBody {
  std::vector<ConvexPiece> pieces;                         ///< collision shape, object frame
  MassProperties mass;                                     ///< at the body's density
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< object frame in the world
};

/// How the model is built; the defaults are docs/physics.md's and why.
struct ModelSettings {
  double timestep = 0.002;  ///< s
  double friction = 0.5;    ///< sliding friction of every geom (MuJoCo takes a pair's larger)
  /// Torsional friction (m) of the fingertip links' geoms, 0 for hard
  /// fingers; a soft-finger robot's contacts get condim 4.
  double torsional_friction = 0.0;
  /// Friction "harder" than the normal force (elliptic cones only): less
  /// creep below the friction limit without a larger friction coefficient.
  double impratio = 10.0;
  int iterations = 50;  ///< Newton solver iterations per step
  /// Contacts and mimic constraints: MuJoCo's soft-constraint time
  /// constant (s; at least 2 timestep) and the impedance reached within
  /// 1 mm. Stiffer than MuJoCo's defaults (0.02 s, 0.9-0.95): with those a
  /// finger driven with 35 N sinks centimetres into a 0.1 kg object and a
  /// mimic jaw lags as far behind its DoF.
  double constraint_timeconst = 0.005;
  double constraint_impedance = 0.99;
  /// Arm position servos: stiff (N m/rad) and damped (N m s/rad, as joint
  /// damping, which MuJoCo integrates implicitly). Every servoed joint gets
  /// the drive inertia (armature) kp (2 timestep)^2, so that no servo
  /// oscillates faster than 1 / (2 timestep) rad/s, which explicit
  /// integration needs (servoArmature()).
  double arm_kp = 20000.0;
  double arm_damping = 200.0;
  /// Links without a URDF <inertial> get their mass from their collision
  /// shapes at this density (kg/m^3).
  double robot_density = 1000.0;
};

/// The drive inertia (kg m^2 or kg) of a joint servoed with stiffness kp:
/// kp (2 timestep)^2, 0.32 kg m^2 for the arm at the defaults.
double servoArmature(double kp, double timestep);

/// MJCF names of the generated model: robot bodies and joints are the URDF
/// names with this prefix (so no link can be called "world"), actuators
/// "servo/<dof name>", mimic constraints "mimic/<joint name>".
inline constexpr const char* kRobotPrefix = "robot/";
inline constexpr const char* kObjectBodyName = "object";

/// The MJCF of robot, scene and object: the robot's links as nested bodies
/// at robot_base (their URDF primitives as geoms, their <inertial> or
/// mass from robot_density), one position servo per DoF (the arm's stiff,
/// the hand's with kp, kv and force range +-effort from
/// robot.handActuation()), a joint equality per mimic joint (joint =
/// offset + multiplier * its DoF's joint), the obstacles as static geoms
/// (a mesh obstacle collides as its convex hull), the object as a free
/// body with an explicit <inertial> and one mesh geom per convex piece.
/// Robot links do not collide with each other. Throws InvalidArgument
/// ("robot.hand_actuation") for a robot without hand actuation.
std::string mjcfScene(const robot::RobotModel& robot, const robot::Scene& scene,
                      const ObjectBody& object, const ModelSettings& settings = {});

/// The MJCF of the scene's obstacles and the object alone (no robot), as
/// mjcfScene writes them.
std::string mjcfObjectScene(const robot::Scene& scene, const ObjectBody& object,
                            const ModelSettings& settings = {});

}  // namespace hfts::physics
