#pragma once
// Every parameter a plan request may set, internal to the planner library:
// declared with their ranges, their defaults from the code and then the
// robot config's planner_defaults, the request's values over them
// (PlanParameters).

#include <ompl/base/GenericParam.h>
#include <ompl/base/SpaceInformation.h>

#include <memory>
#include <vector>

#include "core/invalid_argument.h"
#include "planner/goal_sampler.h"
#include "planner/multi_tree_cbirrt.h"
#include "planner/parameters.h"
#include "planner/plan_request.h"
#include "robot/robot_model.h"

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

  /// The request's preset, its parameters, then its top-level `iterations`.
  void set(const PlanRequest& request) {
    if (request.preset == PlannerPreset::kPaper)
      for (const auto& [name, value] : paperSettings()) setParameter(all, name, value);
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

/// The parameters a request may set for `robot`, with their defaults (the
/// robot config's planner_defaults applied: robot::ModelError naming the
/// one that is unknown or out of range) and ranges.
std::vector<PlannerParameterInfo> plannerParameterInfo(const robot::RobotModel& robot);

}  // namespace hfts::planner
