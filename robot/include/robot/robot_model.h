#pragma once
// The robot: a serial arm carrying a hand, read from a URDF (urdfdom) and a
// robot config file (JSON). Generic over arms and hands; the default is the
// KUKA KR5 sixx R850 + Schunk SDH of robots/kr5_sdh/ (docs/robot.md).

#include <Eigen/Geometry>

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "hfts_db/triangle_mesh.h"

namespace hfts::robot {

/// Thrown for a URDF or robot config that cannot be used. The message names
/// the file and the offending link, joint or key.
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A collision primitive in its link's frame.
struct CollisionShape {
  enum class Type { kBox, kCylinder, kSphere };
  Type type = Type::kSphere;
  /// Box: edge lengths x, y, z. Cylinder: radius, length (along local z), 0.
  /// Sphere: radius, 0, 0.
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
};

/// Half extents of the shape's bounding box in its own frame (a cylinder
/// along z, centred).
Eigen::Vector3d halfExtents(const CollisionShape& shape);

/// A link's mass properties from its URDF <inertial>: the mass (kg), the
/// centre-of-mass frame in the link frame and the inertia tensor (kg m^2)
/// about the centre of mass in that frame.
struct Inertial {
  double mass = 0.0;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
};

struct Link {
  std::string name;
  int parent_joint = -1;  ///< index into joints(); -1 for the root
  std::vector<CollisionShape> shapes;
  /// From the URDF's <inertial>; empty when the URDF gives none (physics
  /// derives the link's mass from its collision shapes, docs/physics.md).
  std::optional<Inertial> inertial;
  /// A body the robot holds (RobotModel::withHeldBody): its surface, link
  /// frame, which collides as a triangle mesh beside the shapes. Null for a
  /// link of the URDF.
  std::shared_ptr<const TriangleMesh> mesh;
};

/// A joint; `dof` is the configuration index that drives it (a mimic joint
/// is driven by the DoF of the joint it mimics), -1 for fixed joints.
struct Joint {
  enum class Type { kFixed, kRevolute, kPrismatic };
  std::string name;
  Type type = Type::kFixed;
  int parent_link = -1;
  int child_link = -1;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  int dof = -1;
  double multiplier = 1.0;  ///< joint value = multiplier * q[dof] + offset
  double offset = 0.0;
  /// The URDF's <limit effort> (N m or N); 0 for fixed joints and when the
  /// URDF gives none. Nominal: the hand's real limits are the config's
  /// hand_actuation.
  double effort = 0.0;
  /// The joint's frame in its parent at value v, from origin and axis (set
  /// by RobotModel::load, for fast forward kinematics): rotation
  /// rotation_fixed + cos(v) rotation_cos + sin(v) rotation_sin (= origin
  /// rotation times the turn about the axis; the last two are zero unless
  /// revolute), translation origin.translation() + v slide (slide = 0
  /// unless prismatic).
  Eigen::Matrix3d rotation_fixed = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d rotation_cos = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d rotation_sin = Eigen::Matrix3d::Zero();
  Eigen::Vector3d slide = Eigen::Vector3d::Zero();
};

/// A fingertip contact point on a hand link, with the outward pad normal.
struct Fingertip {
  std::string name;
  int link = -1;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();
};

/// How the hand's DoF are driven, from the config's optional
/// `hand_actuation` (docs/robot.md): position servos whose force is limited
/// to the hand's published effort per DoF. For physics checks only.
struct HandActuation {
  /// The largest force or torque of each hand DoF's actuator (numHandDofs()
  /// values, > 0; N m for a revolute DoF, N for a prismatic one). For a DoF
  /// that drives mimic joints it is what the DoF's motor delivers in all,
  /// the reactions of its followers included (the Franka Hand's one DoF
  /// carries both jaws' squeeze).
  Eigen::VectorXd efforts;
  double kp = 0.0;     ///< servo stiffness (> 0): N m/rad (revolute), N/m (prismatic)
  double kv = 0.0;     ///< servo damping (>= 0): N m s/rad (revolute), N s/m (prismatic)
  std::string source;  ///< where the efforts come from (the citation)
};

class RobotModel {
 public:
  /// Reads the config and the URDF it names (relative to the config).
  /// Throws ModelError for unreadable files, missing keys, unknown links or
  /// joints, a URDF that is not a tree, or a config that does not match it.
  static RobotModel load(const std::filesystem::path& configPath);

  /// The same from in-memory texts; `what` names the source in errors.
  /// `srdfXml`: the text of the SRDF the config's optional `srdf` names
  /// (its <disable_collisions> pairs join disabled_collisions).
  static RobotModel fromStrings(const std::string& urdfXml, const std::string& configJson,
                                const std::string& what, const std::string& srdfXml = {});

  const std::string& name() const { return name_; }
  /// Configuration size: arm DoF followed by hand DoF.
  int numDofs() const { return static_cast<int>(dof_names_.size()); }
  int numArmDofs() const { return num_arm_dofs_; }
  int numHandDofs() const { return numDofs() - num_arm_dofs_; }
  const std::vector<std::string>& dofNames() const { return dof_names_; }
  const Eigen::VectorXd& lowerLimits() const { return lower_; }
  const Eigen::VectorXd& upperLimits() const { return upper_; }
  const Eigen::VectorXd& maxVelocities() const { return velocity_; }
  /// Joint acceleration limits (rad/s^2) from the config's optional
  /// `max_accelerations`; empty when it has none (then no trajectories).
  const Eigen::VectorXd& maxAccelerations() const { return acceleration_; }
  const Eigen::VectorXd& dofWeights() const { return weights_; }
  const Eigen::VectorXd& home() const { return home_; }
  /// The hand's open posture (hand DoF only) and the pre-grasp opening (rad).
  const Eigen::VectorXd& handOpen() const { return hand_open_; }
  double pregraspOffset() const { return pregrasp_offset_; }
  /// The fingertips' contact model from the config's `contact_model`:
  /// 0 for "hard_finger" (point contacts with friction, the default), the
  /// config's `torsional_friction` gamma (m) for "soft_finger" (contacts
  /// that also resist a torque about their normal, docs/grasp_quality.md).
  double torsionalFriction() const { return torsional_friction_; }
  /// The config's optional `hand_map_normal_weight` (m, > 0): the weight
  /// of a pad-normal error against a fingertip-position error in the hand
  /// map and R(h) (HandMapParameters::normal_weight); 0 when the config
  /// does not set it (the map's default, 0.03 m).
  double handMapNormalWeight() const { return hand_map_normal_weight_; }
  /// The config's optional `planner_defaults`: planner parameter values
  /// (docs/planning.md#parameters) by name, as text, that replace the
  /// planner's defaults for this robot; a plan request's own values still
  /// win. Names and values are checked by the planner when it loads the
  /// robot (planner::PlanningWorld::load), not here.
  const std::map<std::string, std::string>& plannerDefaults() const { return planner_defaults_; }
  /// The config's optional `hand_actuation`: the hand's effort limits and
  /// servo gains for physics checks; empty when the config has none.
  const std::optional<HandActuation>& handActuation() const { return hand_actuation_; }

  /// Links in topological order (a parent before its children); link 0 is
  /// the root (the base link).
  const std::vector<Link>& links() const { return links_; }
  /// Joints in topological order, parallel to the non-root links.
  const std::vector<Joint>& joints() const { return joints_; }
  int linkIndex(const std::string& name) const;  ///< throws ModelError if unknown
  int flangeLink() const { return flange_link_; }
  int palmLink() const { return palm_link_; }
  const std::vector<Fingertip>& fingertips() const { return fingertips_; }
  /// False for an arm without a hand (no hand joints, no fingertips: the
  /// config lists none), which plans motions only.
  bool hasHand() const { return !fingertips_.empty(); }
  /// Pairs of link indices (smaller first) never checked against each other.
  const std::vector<std::pair<int, int>>& disabledCollisions() const { return disabled_; }
  bool isCollisionDisabled(int a, int b) const;
  /// The moving joints between two links (on the chain from one to the
  /// other): 0 when nothing moves them apart. b = -1: the root (the
  /// joints that move link a).
  int movingJointsBetween(int a, int b) const;
  /// Links whose pose depends on a hand DoF (the hand's moving links) plus
  /// the palm: the links that may touch a grasped object's surface are only
  /// the fingertip links among them.
  bool isHandLink(int link) const { return hand_links_[static_cast<std::size_t>(link)]; }

  /// This robot holding a rigid body: one more link, last, named `name`,
  /// fixed to the palm with its frame at `inPalm` (palm frame), colliding
  /// as `mesh` (its own frame). Its collisions with the hand's links are
  /// disabled: the hand holds it (the fingertips touch it) and neither
  /// moves relative to the other while it is held, so what the grasp was
  /// checked for stays true. It is not a hand link. Throws InvalidArgument
  /// ("held_body") for a robot without a hand, a name already in use, a
  /// non-finite pose or a mesh without triangles.
  RobotModel withHeldBody(const std::string& name, const Eigen::Isometry3d& inPalm,
                          std::shared_ptr<const TriangleMesh> mesh) const;
  /// The link withHeldBody added, or -1.
  int heldLink() const { return held_link_; }
  /// This robot with its hand's joints held at `hand` (numHandDofs()
  /// values): their limits (and the hand's home and open postures) become
  /// that posture, so that a planner moves the arm only, as while the hand
  /// holds an object. Throws InvalidArgument ("hand") for a posture of the
  /// wrong size, not finite or outside the limits.
  RobotModel withHandFixed(const Eigen::VectorXd& hand) const;

  /// True when q has numDofs() finite entries within the limits (tolerance
  /// in radians). `why` (optional) receives the first violation.
  bool withinLimits(const Eigen::VectorXd& q, double tolerance = 1e-9,
                    std::string* why = nullptr) const;

 private:
  RobotModel() = default;
  friend class RobotModelBuilder;

  std::string name_;
  std::vector<std::string> dof_names_;
  int num_arm_dofs_ = 0;
  Eigen::VectorXd lower_, upper_, velocity_, acceleration_, weights_, home_, hand_open_;
  double pregrasp_offset_ = 0.0;
  double torsional_friction_ = 0.0;
  double hand_map_normal_weight_ = 0.0;
  std::map<std::string, std::string> planner_defaults_;
  std::optional<HandActuation> hand_actuation_;
  std::vector<Link> links_;
  std::vector<Joint> joints_;
  int flange_link_ = -1;
  int palm_link_ = -1;
  std::vector<Fingertip> fingertips_;
  std::vector<std::pair<int, int>> disabled_;
  std::vector<bool> hand_links_;
  /// movingJointsBetween(a, b) at a * (links + 1) + b, b = links for the root.
  std::vector<int> joints_apart_;
  int held_link_ = -1;

  /// joints_apart_ from the links and joints.
  void countJointsApart();
};

}  // namespace hfts::robot
