// The MJCF text of robot, scene and object (mjcf_scene.h).
#include "physics/mjcf_scene.h"

#include <algorithm>
#include <limits>
#include <sstream>

#include "core/invalid_argument.h"
#include "mjcf_writer.h"

namespace hfts::physics {
namespace {

// Contact groups: a pair of geoms collides when one's contype shares a bit
// with the other's conaffinity. Robot links touch the object and the
// obstacles but not each other; the object touches both; obstacles touch
// the robot and the object (never each other: they are all static).
constexpr int kRobotType = 1, kRobotAffinity = 0;
constexpr int kObjectType = 2, kObjectAffinity = 1 | 4;
constexpr int kStaticType = 4, kStaticAffinity = 1;

// A moving link without <inertial> and without shapes still needs a mass.
constexpr double kPlaceholderMass = 0.01;     // kg
constexpr double kPlaceholderInertia = 1e-6;  // kg m^2

std::string geomType(int type) {
  switch (type) {
    case 0:
      return "box";
    case 1:
      return "cylinder";
    default:
      return "sphere";
  }
}

/// MuJoCo's size of a primitive from ours (Obstacle and CollisionShape use
/// the same numbering and sizes): half extents, radius and half length.
std::string geomSize(int type, const Eigen::Vector3d& size) {
  if (type == 0) return numbers(size / 2.0);
  if (type == 1) return numbers(Eigen::Vector2d(size[0], size[1] / 2.0));
  return number(size[0]);
}

void writePrimitive(XmlElement& geom, int type, const Eigen::Vector3d& size,
                    const Eigen::Isometry3d& pose) {
  geom.attribute("type", geomType(type)).attribute("size", geomSize(type, size));
  writePose(geom, pose);
}

void writeContact(XmlElement& geom, int type, int affinity, int condim, double friction,
                  double torsion) {
  geom.attribute("contype", type)
      .attribute("conaffinity", affinity)
      .attribute("condim", condim)
      .attribute("friction", numbers(Eigen::Vector3d(friction, torsion, 0.0)));
}

class MjcfBuilder {
 public:
  /// `robot` may be null: the scene and the object alone.
  MjcfBuilder(const robot::RobotModel* robot, const robot::Scene& scene, const ObjectBody& object,
              const ModelSettings& settings)
      : robot_(robot), scene_(scene), object_(object), settings_(settings) {
    if (robot == nullptr) return;
    if (!robot->handActuation())
      throw InvalidArgument("robot.hand_actuation",
                            "robot '" + robot->name() + "' has no hand_actuation in its config");
    for (const robot::Fingertip& tip : robot->fingertips()) fingertip_links_.push_back(tip.link);
  }

  std::string build() {
    XmlElement root("mujoco");
    root.attribute("model", "hfts_grasp");
    root.child("compiler").attribute("angle", "radian").attribute("inertiafromgeom", "auto");
    writeOptions(root);
    XmlElement& assets = root.child("asset");
    XmlElement& world = root.child("worldbody");
    writeObstacles(world, assets);
    writeSensedSupport(world);
    if (robot_ != nullptr) writeLink(world, 0);
    writeObject(world, assets);
    if (robot_ != nullptr) {
      writeMimics(root.child("equality"));
      writeActuators(root.child("actuator"));
    }
    std::ostringstream out;
    root.write(out, 0);
    return out.str();
  }

 private:
  void writeOptions(XmlElement& root) const {
    XmlElement& option = root.child("option");
    option.attribute("timestep", number(settings_.timestep))
        .attribute("gravity", "0 0 -9.81")
        .attribute("integrator", "Euler")
        .attribute("cone", "elliptic")
        .attribute("impratio", number(settings_.impratio))
        .attribute("solver", "Newton")
        .attribute("iterations", settings_.iterations);
    // Several contact points between two convex shapes (the object on its
    // support), not MPR's single one.
    option.child("flag").attribute("multiccd", "enable");
    root.child("size").attribute("nconmax", 200).attribute("njmax", 600);
    const std::string solref = numbers(Eigen::Vector2d(settings_.constraint_timeconst, 1.0));
    const std::string solimp = numbers(Eigen::Vector3d(settings_.constraint_impedance - 0.04,
                                                       settings_.constraint_impedance, 0.001));
    XmlElement& defaults = root.child("default");
    defaults.child("geom").attribute("solref", solref).attribute("solimp", solimp);
    defaults.child("equality").attribute("solref", solref).attribute("solimp", solimp);
  }

  void writeObstacles(XmlElement& world, XmlElement& assets) const {
    for (std::size_t i = 0; i < scene_.obstacles.size(); ++i) {
      const robot::Obstacle& obstacle = scene_.obstacles[i];
      if (obstacle.type == robot::Obstacle::Type::kPoints) continue;  // writeSensedSupport
      XmlElement& geom = world.child("geom");
      geom.attribute("name", "obstacle/" + obstacle.name);
      if (obstacle.type == robot::Obstacle::Type::kMesh) {
        // Vertices only: MuJoCo collides a mesh as its convex hull anyway.
        const std::string mesh = "obstacle_mesh_" + std::to_string(i);
        assets.child("mesh")
            .attribute("name", mesh)
            .attribute("vertex", rowNumbers(obstacle.mesh.vertices));
        geom.attribute("type", "mesh").attribute("mesh", mesh);
        writePose(geom, obstacle.pose);
      } else {
        writePrimitive(geom, static_cast<int>(obstacle.type), obstacle.size, obstacle.pose);
      }
      writeContact(geom, kStaticType, kStaticAffinity, 3, settings_.friction, 0.0);
    }
  }

  /// A scene a sensor saw (docs/point_clouds.md): its clouds stay out of
  /// the simulation (thousands of voxel boxes; the planner's collision
  /// checks keep the robot off them), and a plate 2 cm thick whose top is
  /// 1 mm (kRestingClearance) below the object's lowest point stands under the object for the
  /// support the camera saw, whose voxels reach into the object and were carved away.
  void writeSensedSupport(XmlElement& world) const {
    const bool sensed = std::any_of(
        scene_.obstacles.begin(), scene_.obstacles.end(),
        [](const robot::Obstacle& o) { return o.type == robot::Obstacle::Type::kPoints; });
    if (!sensed) return;
    Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()),
                    high = -low;
    for (const ConvexPiece& piece : object_.pieces)
      for (Eigen::Index v = 0; v < piece.vertices.rows(); ++v) {
        const Eigen::Vector3d p = object_.pose * Eigen::Vector3d(piece.vertices.row(v));
        low = low.cwiseMin(p);
        high = high.cwiseMax(p);
      }
    if (!low.allFinite()) return;
    const Eigen::Vector3d size(high.x() - low.x() + 0.1, high.y() - low.y() + 0.1, 0.02);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() << 0.5 * (low.x() + high.x()), 0.5 * (low.y() + high.y()),
        low.z() - robot::kRestingClearance - 0.01;
    XmlElement& geom = world.child("geom");
    geom.attribute("name", "obstacle/sensed_support");
    writePrimitive(geom, static_cast<int>(robot::Obstacle::Type::kBox), size, pose);
    writeContact(geom, kStaticType, kStaticAffinity, 3, settings_.friction, 0.0);
  }

  void writeLink(XmlElement& parent, int index) const {
    const robot::Link& link = robot_->links()[static_cast<std::size_t>(index)];
    XmlElement& body = parent.child("body");
    body.attribute("name", kRobotPrefix + link.name);
    const robot::Joint* joint = nullptr;
    if (link.parent_joint < 0) {
      writePose(body, scene_.robot_base);
    } else {
      joint = &robot_->joints()[static_cast<std::size_t>(link.parent_joint)];
      writePose(body, joint->origin);
      if (joint->type != robot::Joint::Type::kFixed) writeJoint(body, *joint);
    }
    writeInertial(body, link, joint != nullptr && joint->type != robot::Joint::Type::kFixed);
    const bool fingertip = std::count(fingertip_links_.begin(), fingertip_links_.end(), index) > 0;
    for (const robot::CollisionShape& shape : link.shapes) {
      XmlElement& geom = body.child("geom");
      writePrimitive(geom, static_cast<int>(shape.type), shape.size, shape.origin);
      const bool soft = fingertip && settings_.torsional_friction > 0.0;
      writeContact(geom, kRobotType, kRobotAffinity, soft ? 4 : 3, settings_.friction,
                   soft ? settings_.torsional_friction : 0.0);
      geom.attribute("density", number(settings_.robot_density));
    }
    for (std::size_t j = 0; j < robot_->joints().size(); ++j)
      if (robot_->joints()[j].parent_link == index) writeLink(body, robot_->joints()[j].child_link);
  }

  void writeJoint(XmlElement& body, const robot::Joint& joint) const {
    XmlElement& out = body.child("joint");
    out.attribute("name", kRobotPrefix + joint.name)
        .attribute("type", joint.type == robot::Joint::Type::kRevolute ? "hinge" : "slide")
        .attribute("axis", numbers(joint.axis));
    const auto dof = static_cast<Eigen::Index>(joint.dof);
    const double a = joint.offset + joint.multiplier * robot_->lowerLimits()(dof);
    const double b = joint.offset + joint.multiplier * robot_->upperLimits()(dof);
    out.attribute("limited", "true")
        .attribute("range", numbers(Eigen::Vector2d(std::min(a, b), std::max(a, b))));
    const bool arm = joint.dof < robot_->numArmDofs();
    const bool driven = robot_->dofNames()[static_cast<std::size_t>(joint.dof)] == joint.name;
    const double damping = arm ? settings_.arm_damping : robot_->handActuation()->kv;
    const double kp = arm ? settings_.arm_kp : robot_->handActuation()->kp;
    out.attribute("damping", number(driven ? damping : 0.0))
        .attribute("armature", number(servoArmature(kp, settings_.timestep)));
  }

  void writeInertial(XmlElement& body, const robot::Link& link, bool moving) const {
    if (link.inertial) {
      writeInertialElement(body.child("inertial"), link.inertial->mass, link.inertial->origin,
                           link.inertial->inertia);
    } else if (link.shapes.empty() && moving) {
      writeInertialElement(body.child("inertial"), kPlaceholderMass, Eigen::Isometry3d::Identity(),
                           kPlaceholderInertia * Eigen::Matrix3d::Identity());
    }
  }

  void writeObject(XmlElement& world, XmlElement& assets) const {
    XmlElement& body = world.child("body");
    body.attribute("name", kObjectBodyName);
    writePose(body, object_.pose);
    body.child("freejoint").attribute("name", kObjectBodyName);
    Eigen::Isometry3d center = Eigen::Isometry3d::Identity();
    center.translation() = object_.mass.center_of_mass;
    writeInertialElement(body.child("inertial"), object_.mass.mass, center, object_.mass.inertia);
    for (std::size_t i = 0; i < object_.pieces.size(); ++i) {
      const std::string mesh = "object_piece_" + std::to_string(i);
      assets.child("mesh")
          .attribute("name", mesh)
          .attribute("vertex", rowNumbers(object_.pieces[i].vertices));
      XmlElement& geom = body.child("geom");
      geom.attribute("type", "mesh").attribute("mesh", mesh);
      writeContact(geom, kObjectType, kObjectAffinity, 3, settings_.friction, 0.0);
    }
  }

  void writeMimics(XmlElement& equality) const {
    for (const robot::Joint& joint : robot_->joints()) {
      if (joint.dof < 0 || robot_->dofNames()[static_cast<std::size_t>(joint.dof)] == joint.name)
        continue;
      equality.child("joint")
          .attribute("name", "mimic/" + joint.name)
          .attribute("joint1", kRobotPrefix + joint.name)
          .attribute("joint2",
                     kRobotPrefix + robot_->dofNames()[static_cast<std::size_t>(joint.dof)])
          .attribute("polycoef",
                     numbers(Eigen::Matrix<double, 5, 1>(joint.offset, joint.multiplier, 0, 0, 0)));
    }
  }

  void writeActuators(XmlElement& actuators) const {
    const robot::HandActuation& hand = *robot_->handActuation();
    for (int d = 0; d < robot_->numDofs(); ++d) {
      const std::string& name = robot_->dofNames()[static_cast<std::size_t>(d)];
      XmlElement& servo = actuators.child("position");
      servo.attribute("name", "servo/" + name).attribute("joint", kRobotPrefix + name);
      if (d < robot_->numArmDofs()) {
        servo.attribute("kp", number(settings_.arm_kp));
        continue;
      }
      const double effort = hand.efforts(d - robot_->numArmDofs());
      servo.attribute("kp", number(hand.kp))
          .attribute("forcelimited", "true")
          .attribute("forcerange", numbers(Eigen::Vector2d(-effort, effort)));
    }
  }

  const robot::RobotModel* robot_;
  const robot::Scene& scene_;
  const ObjectBody& object_;
  const ModelSettings& settings_;
  std::vector<int> fingertip_links_;
};

}  // namespace

double servoArmature(double kp, double timestep) {
  return kp * 4.0 * timestep * timestep;
}

std::string mjcfScene(const robot::RobotModel& robot, const robot::Scene& scene,
                      const ObjectBody& object, const ModelSettings& settings) {
  return MjcfBuilder(&robot, scene, object, settings).build();
}

std::string mjcfObjectScene(const robot::Scene& scene, const ObjectBody& object,
                            const ModelSettings& settings) {
  return MjcfBuilder(nullptr, scene, object, settings).build();
}

}  // namespace hfts::physics
