// simulateGrasp: the inputs checked, the world built once, every
// perturbation's trial run on its own copy of it, the verdict.
#include "physics/simulate_grasp.h"

#include <algorithm>
#include <cmath>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include "core/invalid_argument.h"
#include "grasp_trial.h"
#include "physics/lift_path.h"
#include "physics/mjcf_scene.h"
#include "physics/object_body.h"
#include "robot/kinematics.h"

namespace hfts::physics {
namespace {

/// The planner's friction, at which robot configs give their soft-finger
/// gamma (= 2/3 mu a for a pad of radius a, docs/grasp_quality.md).
constexpr double kConfigFriction = 0.5;

void checkPositive(double value, const char* field, bool zeroAllowed = false) {
  const bool ok = std::isfinite(value) && (zeroAllowed ? value >= 0.0 : value > 0.0);
  if (!ok)
    throw InvalidArgument(std::string("options.") + field, zeroAllowed
                                                               ? "must be a finite number >= 0"
                                                               : "must be a finite number > 0");
}

void checkConfiguration(const robot::RobotModel& robot, const Eigen::VectorXd& q,
                        const char* field) {
  std::string why;
  if (!robot.withinLimits(q, 1e-6, &why)) throw InvalidArgument(field, why);
}

/// A lift: full configurations within the limits, the arm starting at the
/// grasp's.
void checkLift(const robot::RobotModel& robot, const Eigen::VectorXd& grasp,
               const std::vector<Eigen::VectorXd>& lift) {
  if (lift.empty()) throw InvalidArgument("lift", "has no waypoints");
  for (const Eigen::VectorXd& q : lift) {
    if (q.size() != robot.numDofs())
      throw InvalidArgument(
          "lift", "needs full configurations (" + std::to_string(robot.numDofs()) + " values)");
    checkConfiguration(robot, q, "lift");
  }
  const Eigen::Index arm = robot.numArmDofs();
  if ((lift.front().head(arm) - grasp.head(arm)).cwiseAbs().maxCoeff() > 1e-6)
    throw InvalidArgument("lift", "must start at the grasp's arm configuration");
}

/// The object's body: its collision pieces and its solid's mass at the
/// chosen density, where the scene puts it.
ObjectBody objectBody(const db::ObjectDatabase& object, const robot::Scene& scene, double density) {
  return {collisionPieces(object), objectMassProperties(object, density), scene.target_pose};
}

/// The object's volume over the volume of what it collides as.
double shapeFidelity(const db::ObjectDatabase& object, const std::vector<ConvexPiece>& pieces,
                     double volume) {
  double collision = 0.0;
  for (const ConvexPiece& piece : pieces)
    collision += solidMassProperties(piece.vertices, piece.faces, 1.0).volume;
  return object.geometry.closed ? std::min(1.0, volume / collision) : 1.0;
}

/// The lift's duration: options.lift_time per options.lift_height of the
/// palm's travel along it, no shorter than options.lift_time.
double liftTime(const robot::RobotModel& robot, const std::vector<Eigen::VectorXd>& lift,
                const SimulationOptions& options) {
  const auto palm = [&](const Eigen::VectorXd& q) -> Eigen::Vector3d {
    return robot::forwardKinematics(robot, q)[static_cast<std::size_t>(robot.palmLink())]
        .translation();
  };
  double travel = 0.0;
  Eigen::Vector3d previous = lift.empty() ? Eigen::Vector3d::Zero() : palm(lift.front());
  for (std::size_t i = 1; i < lift.size(); ++i) {
    const Eigen::Vector3d next = palm(lift[i]);
    travel += (next - previous).norm();
    previous = next;
  }
  return options.lift_time * std::max(1.0, travel / options.lift_height);
}

/// What every trial of a grasp on `model` shares.
TrialPlan trialPlan(const robot::RobotModel& robot, const mjModel& model,
                    const Eigen::VectorXd& pregrasp, const Eigen::VectorXd& grasp,
                    std::vector<Eigen::VectorXd> lift, const robot::Scene& scene,
                    const SimulationOptions& options) {
  TrialPlan plan;
  plan.robot = &robot;
  plan.index = indexWorld(model, robot);
  plan.pregrasp = pregrasp;
  plan.grasp = grasp;
  plan.close_limit = closeLimits(robot, pregrasp, grasp);
  plan.close_lead = closeLeads(robot);
  plan.lift = std::move(lift);
  plan.lift_time = liftTime(robot, plan.lift, options);
  plan.object_pose = scene.target_pose;
  plan.options = options;
  return plan;
}

ModelSettings modelSettings(const robot::RobotModel& robot, const SimulationOptions& options) {
  ModelSettings settings;
  settings.timestep = options.timestep;
  settings.friction = options.friction;
  settings.torsional_friction = robot.torsionalFriction() * options.friction / kConfigFriction;
  return settings;
}

}  // namespace

void validateOptions(const SimulationOptions& options) {
  if (options.density) checkPositive(*options.density, "density");
  checkPositive(options.friction, "friction", true);
  checkPositive(options.lift_height, "lift_height");
  checkPositive(options.lift_time, "lift_time");
  checkPositive(options.settle_time, "settle_time", true);
  checkPositive(options.close_time, "close_time");
  checkPositive(options.hold_time, "hold_time", true);
  checkPositive(options.disturbance_time, "disturbance_time", true);
  checkPositive(options.max_displacement, "max_displacement");
  checkPositive(options.max_rotation, "max_rotation");
  checkPositive(options.record_rate, "record_rate", true);
  if (!(options.min_held_fraction >= 0.0 && options.min_held_fraction <= 1.0))
    throw InvalidArgument("options.min_held_fraction", "must be in [0, 1]");
  if (!(options.timestep > 0.0 && options.timestep <= 0.005))
    throw InvalidArgument("options.timestep", "must be in (0, 0.005] s");
}

namespace {

/// The compiled model of an MJCF scene, from the last few compiled: a
/// planner's goal checks in one request share the robot, the scene and the
/// object (the configurations are not in the model), and an object of
/// hundreds of convex parts is slow to compile.
std::shared_ptr<const mjModel> compiledScene(const std::string& xml) {
  constexpr std::size_t kKept = 4;
  static std::mutex mutex;
  static std::list<std::pair<std::string, std::shared_ptr<const mjModel>>> kept;  // newest first
  {
    const std::lock_guard<std::mutex> lock(mutex);
    for (auto it = kept.begin(); it != kept.end(); ++it)
      if (it->first == xml) {
        kept.splice(kept.begin(), kept, it);
        return it->second;
      }
  }
  std::shared_ptr<const mjModel> model(compileMjcf(xml).release(), ModelDeleter{});
  const std::lock_guard<std::mutex> lock(mutex);
  kept.emplace_front(xml, model);
  if (kept.size() > kKept) kept.pop_back();
  return model;
}

}  // namespace

void prepareSimulation(const robot::RobotModel& robot, const robot::Scene& scene,
                       const db::ObjectDatabase& object, const SimulationOptions& options) {
  validateOptions(options);
  if (!robot.handActuation()) return;
  const ObjectBody body = objectBody(object, scene, objectDensity(object, options.density));
  compiledScene(mjcfScene(robot, scene, body, modelSettings(robot, options)));
}

GraspVerdict simulateGrasp(const robot::CollisionModel& collision, const robot::Scene& scene,
                           const db::ObjectDatabase& object, const Eigen::VectorXd& pregrasp,
                           const Eigen::VectorXd& grasp, const SimulationOptions& options,
                           const std::vector<Eigen::VectorXd>* lift) {
  const robot::RobotModel& robot = collision.robot;
  checkConfiguration(robot, pregrasp, "pregrasp");
  checkConfiguration(robot, grasp, "grasp");
  validateOptions(options);
  if (lift != nullptr) checkLift(robot, grasp, *lift);
  if (!robot.handActuation())
    throw InvalidArgument("robot.hand_actuation",
                          "robot '" + robot.name() + "' has no hand_actuation in its config");

  GraspVerdict verdict;
  verdict.density = objectDensity(object, options.density);
  const ObjectBody body = objectBody(object, scene, verdict.density);
  verdict.mass = body.mass.mass;
  verdict.collision_shape = collisionShapeName(object);
  verdict.shape_fidelity = shapeFidelity(object, body.pieces, body.mass.volume);

  // Polled between the set-up's costly steps too (tens of milliseconds each).
  const auto stopped = [&] { return verdict.stopped = options.stop && options.stop(); };
  if (stopped()) return verdict;
  std::vector<Eigen::VectorXd> waypoints;
  if (lift != nullptr) {
    waypoints = *lift;
    verdict.lift_direction = "plan";
  } else {
    LiftPlan planned = planLift(collision, scene, grasp, options.lift_height, &object.geometry);
    waypoints = std::move(planned.line.waypoints);
    verdict.lift_direction = planned.direction;
  }
  if (stopped()) return verdict;

  const std::shared_ptr<const mjModel> nominal =
      compiledScene(mjcfScene(robot, scene, body, modelSettings(robot, options)));
  const TrialPlan plan =
      trialPlan(robot, *nominal, pregrasp, grasp, std::move(waypoints), scene, options);
  const std::vector<Perturbation> trials = perturbations(options.perturb);
  const auto total = static_cast<double>(trials.size());
  int held = 0, dropped = 0;
  for (const Perturbation& perturbation : trials) {
    if (stopped()) break;
    const ModelPtr model = perturbedModel(*nominal, plan.index, robot.numArmDofs(), perturbation);
    std::vector<MotionSample>* motion = verdict.trials.empty() ? &verdict.nominal_motion : nullptr;
    verdict.trials.push_back(runTrial(*model, plan, perturbation.name, motion));
    if (verdict.trials.back().stopped) {
      verdict.stopped = true;
      break;
    }
    (verdict.trials.back().held ? held : dropped) += 1;
    if (options.stop_when_lost && (total - dropped) / total < options.min_held_fraction - 1e-12)
      break;
  }
  verdict.held_fraction = static_cast<double>(held) / total;
  verdict.held = !verdict.stopped && verdict.held_fraction >= options.min_held_fraction - 1e-12;
  return verdict;
}

}  // namespace hfts::physics

namespace hfts::physics {

PlaceVerdict simulatePickAndPlace(const robot::CollisionModel& collision, const robot::Scene& scene,
                                  const db::ObjectDatabase& object, const Eigen::VectorXd& pregrasp,
                                  const Eigen::VectorXd& grasp, const PlaceMotion& motion,
                                  const SimulationOptions& options, const RestOptions& rest) {
  const robot::RobotModel& robot = collision.robot;
  checkConfiguration(robot, pregrasp, "pregrasp");
  checkConfiguration(robot, grasp, "grasp");
  validateOptions(options);
  validateRestOptions(rest);
  if (!robot.handActuation())
    throw InvalidArgument("robot.hand_actuation",
                          "robot '" + robot.name() + "' has no hand_actuation in its config");
  const auto sized = [&](const Eigen::VectorXd& q) { return q.size() == robot.numDofs(); };
  if (motion.lift.empty() || motion.times.size() < 2 ||
      motion.times.size() != motion.positions.size() ||
      !std::all_of(motion.lift.begin(), motion.lift.end(), sized) ||
      !std::all_of(motion.positions.begin(), motion.positions.end(), sized))
    throw InvalidArgument("motion", "needs a lift and a trajectory of full configurations (" +
                                        std::to_string(robot.numDofs()) + " values), one per time");
  for (std::size_t i = 1; i < motion.times.size(); ++i)
    if (!(motion.times[i] > motion.times[i - 1]))
      throw InvalidArgument("motion", "its times must increase");
  if (!(motion.release_start >= motion.times.front() &&
        motion.release_start <= motion.times.back()))
    throw InvalidArgument("motion", "release_start must lie within its times");

  const ObjectBody body = objectBody(object, scene, objectDensity(object, options.density));
  const std::shared_ptr<const mjModel> model =
      compiledScene(mjcfScene(robot, scene, body, modelSettings(robot, options)));
  TrialPlan plan = trialPlan(robot, *model, pregrasp, grasp, motion.lift, scene, options);
  plan.place = &motion;
  plan.rest = rest;
  std::vector<MotionSample> samples;
  PlaceVerdict verdict = runPlaceTrial(*model, plan, &samples);
  verdict.motion = std::move(samples);
  return verdict;
}

}  // namespace hfts::physics
