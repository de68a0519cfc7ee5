#pragma once
// One plan's problem, internal to the planner library: the scene as
// requested with its collision checker, OMPL space information, settings
// (plan_settings.h) and HFTS (Problem), and why planning cannot start
// in it (checkScene, checkGraspable). planGrasp, the searches (plan_search.h) and
// holdability build on it.

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

namespace hfts::planner {

namespace ob = ompl::base;

/// The request's start (else the scene's for this robot, else home),
/// checked (InvalidArgument "start").
Eigen::VectorXd startOf(const robot::RobotModel& robot, const PlanRequest& request);

/// The request's object: `object`, else the scene's target.
std::string objectNameOf(const PlanRequest& request);

/// One plan's problem, set up in order: the settings, the scene as
/// requested, its collision checker and OMPL space information, the
/// object's HFTS.
struct Problem {
  Problem(const PlanningWorld& w, const db::ObjectDatabase& o, const PlanRequest& request,
          Eigen::VectorXd q0)
      : world(w),
        object(o),
        settings(resolveSettings(w.robot(), request)),
        goals(goalSamplingSettings(settings, w.robot())),
        scene(sceneOf(request, o)),
        start(std::move(q0)),
        seed(request.seed),
        explored(request.explored),
        simulation(request.simulation),
        checker(w.robot(), scene, &o.geometry, w.collisionMesh(o.name), w.surface(o.name)),
        si(makeSpaceInformation(w.robot(), checker, kTreeResolution)),
        planner(plannerFor(si, settings)),
        // A robot whose fingertips have no measurable pad is not masked.
        usable(
            !settings.heuristics.mask_contacts || w.padRadius() <= grasp::kContactMaskClearance
                ? std::vector<bool>{}
                : grasp::fingertipReachableContacts(o, scene.target_pose, checker, w.padRadius())),
        space(o, static_cast<int>(w.robot().fingertips().size()),
              usable.empty() ? nullptr : &usable) {
    checker.setSphereTier(settings.execution.sphere_tier);
    checker.setMaxPenetration(settings.goal.max_penetration);
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
  const PlanSettings settings;       ///< resolved (resolveSettings)
  const GoalSamplingSettings goals;  ///< goal sampling's part of them
  const robot::Scene scene;
  const Eigen::VectorXd start;
  const std::uint64_t seed;
  const bool explored;                          ///< record the goal hierarchy cache's nodes
  const physics::SimulationOptions simulation;  ///< of physics_check and validate
  robot::CollisionChecker checker;
  const ob::SpaceInformationPtr si;
  /// Algorithm 1's planner, with the settings applied.
  const std::shared_ptr<MultiTreeCBiRRT> planner;
  /// Contacts a fingertip can touch here (empty: mask_contacts off, all).
  const std::vector<bool> usable;
  const grasp::HftsSpace space;
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

/// The time limit (counted from `began`) or the cancel flag.
ob::PlannerTerminationCondition terminationCondition(double timeLimit,
                                                     std::chrono::steady_clock::time_point began,
                                                     const std::atomic<bool>* cancel);

}  // namespace hfts::planner
