#include "planner/grasp_validation.h"

#include <cmath>
#include <string>

#include "core/invalid_argument.h"
#include "grasp/grasp_quality.h"
#include "grasp/hand_closing.h"
#include "grasp/load_capacity.h"
#include "physics/object_body.h"
#include "robot/kinematics.h"
#include "robot/object_surface.h"

namespace hfts::planner {
namespace {

void checkConfiguration(const robot::RobotModel& robot, const Eigen::VectorXd& q,
                        const std::string& field) {
  if (q.size() != robot.numDofs())
    throw InvalidArgument(field, std::to_string(robot.numDofs()) + " values expected, got " +
                                     std::to_string(q.size()));
  if (!q.allFinite()) throw InvalidArgument(field, "values must be finite");
  std::string why;
  if (!robot.withinLimits(q, 1e-9, &why)) throw InvalidArgument(field, why);
}

void checkOptions(const GraspCheckOptions& o) {
  if (!(o.min_epsilon >= 0.0) || !std::isfinite(o.min_epsilon))
    throw InvalidArgument("check.min_epsilon", "must be a finite number >= 0");
  if (!(o.max_penetration >= 0.0) || !std::isfinite(o.max_penetration))
    throw InvalidArgument("check.max_penetration", "must be a finite number >= 0 (m)");
  if (!(o.resolution > 0.0) || !std::isfinite(o.resolution))
    throw InvalidArgument("check.resolution", "must be a finite number > 0");
  if (!(o.friction > 0.0) || !std::isfinite(o.friction))
    throw InvalidArgument("check.friction", "must be a finite number > 0");
}

/// The pose of the robot's palm at q in the object's frame.
Eigen::Isometry3d palmInObject(const robot::RobotModel& robot, const robot::Scene& scene,
                               const Eigen::VectorXd& q) {
  const robot::LinkPoses poses = robot::forwardKinematics(robot, q);
  return scene.target_pose.inverse() * scene.robot_base *
         poses[static_cast<std::size_t>(robot.palmLink())];
}

/// Epsilon at the contacts a closed hand touches, with the robot's contact
/// model and the object's centre of mass and rho.
double contactEpsilon(const robot::RobotModel& robot, const db::ObjectGeometry& object,
                      const grasp::HandClosure& closure, const GraspCheckOptions& options) {
  const grasp::GraspContacts contacts = closure.contacts();
  grasp::GraspQualityRequest q;
  q.positions = contacts.positions;
  q.normals = -contacts.outward_normals;
  q.center = object.center_of_mass;
  q.torque_scale = object.rho;
  q.friction = options.friction;
  q.torsional_friction = robot.torsionalFriction();
  return grasp::graspQuality(q).epsilon;
}

/// grasp::loadCapacity of the closed hand at the full configuration q.
double loadCapacityOf(const robot::RobotModel& robot, const robot::Scene& scene,
                      const db::ObjectDatabase& object, const robot::ObjectSurface& surface,
                      const grasp::HandClosure& closure, const Eigen::VectorXd& q,
                      const std::optional<double>& density) {
  const double mass =
      physics::objectMassProperties(object, physics::objectDensity(object, density)).mass;
  return grasp::loadCapacity(grasp::loadRequest(robot, q, scene.robot_base, closure,
                                                scene.target_pose, object.geometry.center_of_mass,
                                                mass, &surface))
      .factor;
}

double fingertipDepth(const robot::RobotModel& robot, const robot::ObjectSurface& surface,
                      const robot::Scene& scene, const Eigen::VectorXd& q) {
  constexpr double kTolerance = 5e-5;
  const robot::LinkPoses poses = robot::forwardKinematics(robot, q);
  const Eigen::Isometry3d baseInObject = scene.target_pose.inverse() * scene.robot_base;
  double depth = 0.0;
  for (const robot::Fingertip& tip : robot.fingertips()) {
    const auto link = static_cast<std::size_t>(tip.link);
    depth = std::max(
        depth, surface.linkDepth(robot.links()[link], baseInObject * poses[link], kTolerance));
  }
  return depth;
}

/// The first criterion the check does not meet, in words.
std::string problemOf(const GraspCheck& c, const GraspCheckOptions& o,
                      const grasp::HandClosure& closure, const robot::RobotModel& robot,
                      const std::string& collision) {
  if (!c.pads_touch) return "closed from the pre-grasp, " + closure.failure(robot);
  if (!c.clear) return "collides under the grasp rule: " + collision;
  if (c.penetration > o.max_penetration)
    return "a fingertip is " + std::to_string(1000.0 * c.penetration) +
           " mm inside the object (max_penetration " + std::to_string(1000.0 * o.max_penetration) +
           " mm)";
  if (!(c.epsilon > 0.0)) return "no force closure at the contacts the pads touch";
  if (c.epsilon < o.min_epsilon)
    return "epsilon " + std::to_string(c.epsilon) + " at the contacts the pads touch is below " +
           "min_epsilon " + std::to_string(o.min_epsilon);
  return "";
}

}  // namespace

Validation validateGrasp(const PlanningWorld& world, const ValidationRequest& request) {
  const robot::RobotModel& robot = world.robot();
  checkConfiguration(robot, request.pregrasp, "pregrasp");
  checkConfiguration(robot, request.grasp, "grasp");
  checkOptions(request.check);
  const std::string& name = request.scene.target_object;
  const db::ObjectDatabase* object = world.object(name);
  if (object == nullptr)
    throw InvalidArgument("scene.target_object", "unknown object '" + name + "'");
  if (request.physics) physics::validateOptions(request.simulation);
  const robot::ObjectSurface& surface = *world.surface(name);
  const int arm = robot.numArmDofs(), hand = robot.numHandDofs();

  // The hand closes as it would on the robot: the arm holds the pre-grasp's
  // palm (no centring: a plan has done that), the fingers move towards the
  // grasp's posture and on until they touch.
  grasp::ClosingOptions closing;
  closing.centering_rounds = 0;
  const grasp::HandClosure closure =
      grasp::HandCloser(world.collisionModel(), surface, closing)
          .close(palmInObject(robot, request.scene, request.pregrasp), request.pregrasp.tail(hand),
                 request.grasp.tail(hand));
  Validation out;
  GraspCheck& c = out.check;
  c.executed = request.pregrasp;
  c.executed.tail(hand) = closure.hand;
  c.closing_difference = (request.grasp.tail(hand) - closure.hand).cwiseAbs().maxCoeff();
  c.pads_touch = closure.touches();
  if (c.pads_touch) c.epsilon = contactEpsilon(robot, object->geometry, closure, request.check);
  c.penetration = fingertipDepth(robot, surface, request.scene, c.executed);
  if (c.pads_touch && robot.handActuation())
    c.load_capacity = loadCapacityOf(robot, request.scene, *object, surface, closure, c.executed,
                                     request.simulation.density);
  robot::CollisionChecker checker(world.collisionModel(), request.scene, &object->geometry,
                                  world.collisionMesh(name), &surface);
  checker.setMaxPenetration(request.check.max_penetration);
  robot::CollisionPair pair;
  c.clear = !checker.inCollision(request.pregrasp, &pair) &&
            checker.isMotionValid(request.pregrasp, c.executed, request.check.resolution,
                                  robot::CollisionRequest::grasp(), &pair);
  c.problem = problemOf(c, request.check, closure, robot, pair.first + " touches " + pair.second);
  if ((request.grasp.head(arm) - request.pregrasp.head(arm)).cwiseAbs().maxCoeff() > 1e-9 &&
      c.problem.empty())
    c.problem = "the arm moves between the pre-grasp and the grasp";
  if (request.physics)
    out.physics = physics::simulateGrasp(world.collisionModel(), request.scene, *object,
                                         request.pregrasp, c.executed, request.simulation,
                                         request.lift.empty() ? nullptr : &request.lift);
  return out;
}

}  // namespace hfts::planner
