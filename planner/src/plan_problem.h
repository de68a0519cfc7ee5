#pragma once
// One plan's problem, internal to the planner library: the parameters a
// request may set merged over the robot's defaults (PlanParameters), the
// scene as requested with its collision checker, OMPL space information and
// HFTS (Problem), and why planning cannot start in it (checkScene,
// checkGraspable). planGrasp, the searches (plan_search.h) and
// holdability build on it.

#include <ompl/base/PlannerTerminationCondition.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "grasp/contact_mask.h"
#include "grasp/hfts_space.h"
#include "hfts_db/invalid_argument.h"
#include "planner/configuration_space.h"
#include "planner/goal_sampler.h"
#include "planner/grasp_motion_planner.h"
#include "planner/multi_tree_cbirrt.h"
#include "planner/parameters.h"
#include "robot/collision_checker.h"

namespace hfts::planner {

namespace ob = ompl::base;

constexpr double kTreeResolution = 0.02;  // collision_resolution default (Eq. 3 metric)
/// Racing copies a request may ask for (parameter `threads`).
const ParameterRange kThreadsRange{1, 1, 32};

/// OMPL's console at warnings and above, once per process.
void quietOmpl();

/// Every parameter a request may set, in one set: the multi-tree planner's
/// own (its smoothing's included) and goal sampling's (the samplers' and
/// the objective's), merged. The RRTConnect baseline reads the same names.
struct PlanParameters {
  /// The defaults for `robot`: its fingertips' contact model, for two
  /// fingertips unstable pairs ranked by reach and Q = 0 for pairs the jaws
  /// cannot hold (grasp_objective.h), then
  /// its config's `planner_defaults` (robot::ModelError naming the one
  /// that is unknown or out of range).
  PlanParameters(const ob::SpaceInformationPtr& si, const robot::RobotModel& robot)
      : planner(std::make_shared<MultiTreeCBiRRT>(si)) {
    all.include(planner->params());
    declareParameters(all, goals);
    declareParameter(all, "sphere_tier", {0, 1, 1}, sphereTier);
    declareParameter(all, "threads", kThreadsRange, threads);  // planGrasp reads it
    declareParameter(all, "physics_check", {0, 1, 1}, physicsCheck);
    goals.objective.torsional_friction = robot.torsionalFriction();
    goals.objective.unstable_by_reach = robot.fingertips().size() == 2 ? 1 : 0;
    goals.objective.fit_check = robot.fingertips().size() == 2 ? 1 : 0;
    for (const auto& [name, value] : robot.plannerDefaults()) {
      try {
        setParameter(all, name, value);
      } catch (const InvalidArgument& e) {
        throw robot::ModelError("robot config '" + robot.name() + "': planner_defaults." + name +
                                ": " + e.problem());
      }
    }
  }
  /// The request's parameters over the robot's defaults.
  PlanParameters(const ob::SpaceInformationPtr& si, const PlanRequest& request,
                 const robot::RobotModel& robot)
      : PlanParameters(si, robot) {
    set(request);
  }
  PlanParameters(const PlanParameters&) = delete;
  PlanParameters& operator=(const PlanParameters&) = delete;

  /// The request's parameters, then its top-level `iterations`.
  void set(const PlanRequest& request) {
    for (const auto& [name, value] : request.parameters) setParameter(all, name, value);
    if (!request.iterations) return;
    try {
      setParameter(all, "iterations", std::to_string(*request.iterations));
    } catch (const InvalidArgument& e) {
      throw InvalidArgument("iterations", e.problem());
    }
  }

  std::shared_ptr<MultiTreeCBiRRT> planner;
  GoalSamplingSettings goals;
  /// 1: collision checks in two tiers (spheres, then FCL on the touching
  /// pairs); 0: FCL alone. The same answers either way (docs/collision.md).
  int sphereTier = 1;
  /// Racing copies of the search (planGrasp); each copy is one thread.
  int threads = 1;
  /// 1: a goal the trees reach ends the search only when its grasp holds
  /// in physics (physics::simulateGrasp with the request's simulation
  /// options); else its tree is dropped and the search goes on. 0: every
  /// reached goal ends it (the paper's Algorithm 1).
  int physicsCheck = 1;
  ob::ParamSet all;
};

/// The request's start (else the scene's for this robot, else home),
/// checked (InvalidArgument "start").
Eigen::VectorXd startOf(const robot::RobotModel& robot, const PlanRequest& request);

/// The request's object: `object`, else the scene's target.
std::string objectNameOf(const PlanRequest& request);

/// One plan's problem, set up in order: the scene as requested, its
/// collision checker and OMPL space information, the parameters, the
/// object's HFTS.
struct Problem {
  Problem(const PlanningWorld& w, const db::ObjectDatabase& o, const PlanRequest& request,
          Eigen::VectorXd q0)
      : world(w),
        object(o),
        scene(sceneOf(request, o)),
        start(std::move(q0)),
        seed(request.seed),
        explored(request.explored),
        simulation(request.simulation),
        checker(w.robot(), scene, &o.geometry, w.collisionMesh(o.name), w.surface(o.name)),
        si(makeSpaceInformation(w.robot(), checker, kTreeResolution)),
        parameters(si, request, w.robot()),
        // A robot whose fingertips have no measurable pad is not masked.
        usable(
            parameters.goals.mask_contacts == 0 || w.padRadius() <= grasp::kContactMaskClearance
                ? std::vector<bool>{}
                : grasp::fingertipReachableContacts(o, scene.target_pose, checker, w.padRadius())),
        space(o, static_cast<int>(w.robot().fingertips().size()),
              usable.empty() ? nullptr : &usable) {
    checker.setSphereTier(parameters.sphereTier != 0);
    checker.setMaxPenetration(parameters.goals.max_penetration);
  }

  /// The request's object where the request puts it: at object_pose, or
  /// at the scene's target pose (resting on its support when it has one).
  static robot::Scene sceneOf(const PlanRequest& request, const db::ObjectDatabase& object) {
    robot::Scene s = request.scene;
    s.target_object = object.name;
    s.target_pose = request.object_pose
                        ? *request.object_pose
                        : robot::targetPose(request.scene, object.geometry.mesh_vertices);
    s.target_rest_on.clear();  // placed
    return s;
  }

  const PlanningWorld& world;
  const db::ObjectDatabase& object;
  const robot::Scene scene;
  const Eigen::VectorXd start;
  const std::uint64_t seed;
  const bool explored;                          ///< record the goal hierarchy cache's nodes
  const physics::SimulationOptions simulation;  ///< of physics_check and validate
  robot::CollisionChecker checker;
  const ob::SpaceInformationPtr si;
  PlanParameters parameters;
  /// Contacts a fingertip can touch here (empty: mask_contacts off, all).
  const std::vector<bool> usable;
  const grasp::HftsSpace space;
};

/// Whether the target intersects an obstacle where it stands (kNone: not).
std::pair<PlanFailure, std::string> checkTarget(Problem& p);

/// Why planning cannot start in this scene (kNone: it can): checkTarget,
/// then the start configuration.
std::pair<PlanFailure, std::string> checkScene(Problem& p);

/// Why no grasp can be stable where the object stands (kNone: one may be).
std::pair<PlanFailure, std::string> checkGraspable(const Problem& p);

/// The time limit (counted from `began`) or the cancel flag.
ob::PlannerTerminationCondition terminationCondition(double timeLimit,
                                                     std::chrono::steady_clock::time_point began,
                                                     const std::atomic<bool>* cancel);

}  // namespace hfts::planner
