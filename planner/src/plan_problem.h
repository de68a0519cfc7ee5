#pragma once
// One plan's problem, internal to the planner library: what the searches
// of a request share read-only (SharedProblem: settings, the scene as
// requested with its collision scene, the contact mask and HFTS), one
// search's own part (Problem: collision checker, OMPL space information,
// planner), and why planning cannot start (checkScene, checkGraspable).
// planGrasp, the searches (plan_search.h) and holdability build on it.

#include <ompl/base/PlannerTerminationCondition.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/invalid_argument.h"
#include "grasp/contact_mask.h"
#include "grasp/hfts_space.h"
#include "planner/configuration_space.h"
#include "planner/goal_sampler.h"
#include "planner/multi_tree_cbirrt.h"
#include "planner/plan_request.h"
#include "planner/plan_result.h"
#include "planner/planning_world.h"
#include "planner_parameters.h"
#include "robot/collision_checker.h"
#include "robot/sensed_scene.h"

namespace hfts::planner {

namespace ob = ompl::base;

/// The request's start (else the scene's for this robot, else home),
/// checked (InvalidArgument "start").
Eigen::VectorXd startOf(const robot::RobotModel& robot, const PlanRequest& request);

/// The request's object: `object`, else the scene's target.
std::string objectNameOf(const PlanRequest& request);

/// Throws InvalidArgument for a time limit that is negative or not finite
/// ("time_limit") and a trajectory rate outside [0, kMaxTrajectoryRate]
/// ("trajectory_rate").
void checkLimits(const PlanRequest& request);

/// Whether the start collides (kStartInCollision, naming the contact) or
/// not (kNone).
std::pair<PlanFailure, std::string> checkStart(robot::CollisionChecker& checker,
                                               const Eigen::VectorXd& start);

/// What every search of one plan request shares, read-only (the racing
/// copies too, which differ only in their seed): the settings, the scene as
/// requested with its collision scene, the contacts a fingertip can touch
/// and the object's HFTS over them. Built once per request.
struct SharedProblem {
  SharedProblem(const PlanningWorld& w, const db::ObjectDatabase& o, const PlanRequest& request)
      : world(w),
        object(o),
        settings(resolveSettings(w.robot(), request)),
        goals(goalSamplingSettings(settings, w.robot())),
        scene(sceneOf(request, o, w.robot())),
        explored(request.explored),
        simulation(request.simulation),
        lift(request.goals.empty() ? request.lift : std::nullopt),
        collision(std::make_shared<const robot::CollisionScene>(
            w.collisionModel(), scene, &o.geometry, w.collisionMesh(o.name), w.surface(o.name),
            settings.path.clearance)),
        // A robot whose fingertips have no measurable pad is not masked.
        usable(!settings.heuristics.mask_contacts || w.padRadius() <= grasp::kContactMaskClearance
                   ? std::vector<bool>{}
                   : grasp::fingertipReachableContacts(o, scene.target_pose, *collision,
                                                       w.padRadius())),
        space(o, static_cast<int>(w.robot().fingertips().size()),
              usable.empty() ? nullptr : &usable) {}

  /// The request's object where the request puts it: at object_pose, or
  /// at the scene's target pose (resting on its support when it has one);
  /// sensed obstacles without what another view saw through, what the
  /// sensor saw of the object and of the robot at its start; an object
  /// built from views with the space they could not see free beside it as
  /// an obstacle (docs/point_clouds.md).
  static robot::Scene sceneOf(const PlanRequest& request, const db::ObjectDatabase& object,
                              const robot::RobotModel& robot) {
    robot::Scene s = request.scene;
    s.target_object = object.name;
    s.target_pose = request.object_pose
                        ? *request.object_pose
                        : robot::targetPose(request.scene, object.geometry.mesh_vertices);
    s.target_rest_on.clear();  // placed
    return robot::asPlannerSees(s, object, robot, startOf(robot, request));
  }

  const PlanningWorld& world;
  const db::ObjectDatabase& object;
  const PlanSettings settings;       ///< resolved (resolveSettings)
  const GoalSamplingSettings goals;  ///< goal sampling's part of them
  const robot::Scene scene;
  const bool explored;                          ///< record the goal hierarchy cache's nodes
  const physics::SimulationOptions simulation;  ///< of physics_check and validate
  const std::optional<LiftOptions> lift;        ///< every goal's lift (none: no lift)
  const std::shared_ptr<const robot::CollisionScene> collision;
  /// Contacts a fingertip can touch here (empty: mask_contacts off, all).
  const std::vector<bool> usable;
  const grasp::HftsSpace space;
};

/// One search's problem: the shared part's names, and what the search
/// changes (its collision checker over the shared scene, OMPL space
/// information, Algorithm 1's planner) and its seed. Sets up in
/// microseconds beside the shared part (planner_benchmark's BM_PlanStartUp).
struct Problem {
  Problem(const SharedProblem& shared, std::uint64_t seedOfSearch, Eigen::VectorXd q0)
      : world(shared.world),
        object(shared.object),
        settings(shared.settings),
        goals(shared.goals),
        scene(shared.scene),
        start(std::move(q0)),
        seed(seedOfSearch),
        explored(shared.explored),
        simulation(shared.simulation),
        lift(shared.lift),
        checker(shared.collision),
        si(makeSpaceInformation(world.robot(), checker, kTreeResolution)),
        planner(plannerFor(si, settings)),
        usable(shared.usable),
        space(shared.space) {
    checker.setSphereTier(settings.execution.sphere_tier);
    checker.setMaxPenetration(settings.goal.max_penetration);
    planner->setCertification(settings.path.certify ? &world.motionBound() : nullptr);
  }

  /// Algorithm 1's planner with the settings applied; also the space's:
  /// the motion validator's resolution and the DoF weights, which every
  /// algorithm's motions use.
  static std::shared_ptr<MultiTreeCBiRRT> plannerFor(const ob::SpaceInformationPtr& si,
                                                     const PlanSettings& settings) {
    auto planner = std::make_shared<MultiTreeCBiRRT>(si);
    planner->applySettings(settings);
    return planner;
  }

  const PlanningWorld& world;
  const db::ObjectDatabase& object;
  const PlanSettings& settings;
  const GoalSamplingSettings& goals;
  const robot::Scene& scene;
  const Eigen::VectorXd start;
  const std::uint64_t seed;
  const bool explored;
  const physics::SimulationOptions& simulation;
  const std::optional<LiftOptions>& lift;
  robot::CollisionChecker checker;
  const ob::SpaceInformationPtr si;
  /// Algorithm 1's planner, with the settings applied.
  const std::shared_ptr<MultiTreeCBiRRT> planner;
  const std::vector<bool>& usable;
  const grasp::HftsSpace& space;
};

/// Whether the target intersects an obstacle where it stands (kNone: not).
std::pair<PlanFailure, std::string> checkTarget(Problem& p);

/// Whether the object lies beyond every fingertip's reach (kNone: it may
/// not): its surface farther from the arm's first axis than
/// robot::fingertipReach's ball and a pad's radius, exactly (the
/// surface's nearest point). An object without a surface is not checked.
std::pair<PlanFailure, std::string> checkReach(const Problem& p);

/// Why planning cannot start in this scene (kNone: it can): checkTarget,
/// checkReach, then the start configuration.
std::pair<PlanFailure, std::string> checkScene(Problem& p);

/// Why no grasp can be stable where the object stands (kNone: one may be).
std::pair<PlanFailure, std::string> checkGraspable(const Problem& p);

/// searchTimeLimit(timeLimit) (counted from `began`) or the cancel flag.
ob::PlannerTerminationCondition terminationCondition(double timeLimit,
                                                     std::chrono::steady_clock::time_point began,
                                                     const std::atomic<bool>* cancel);

}  // namespace hfts::planner
