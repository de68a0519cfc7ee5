#pragma once
// Grasp-and-motion planning as one call: PlanRequest -> PlanResult. Builds
// the collision checker, the HFTS goal sampler (or the decoupled baseline)
// and the multi-tree CBiRRT for a request and runs them. OMPL stays behind
// this header (see multi_tree_cbirrt.h for the planner itself).

#include <Eigen/Geometry>

#include <atomic>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "planner/plan_request.h"
#include "planner/plan_result.h"
#include "planner/planning_world.h"

namespace hfts::planner {

/// Every parameter a request may set for the world's robot, with its default
/// (the robot config's planner_defaults applied) and range.
std::vector<PlannerParameterInfo> plannerParameters(const PlanningWorld& world);

/// A successful plan as an animated binary glTF (robot/plan_export.h):
/// the request's scene, the object where it was planned, the robot moving
/// along the result's trajectory, the contacts and the path; with a
/// physics verdict (validate, or the planner's physics_check) also the
/// simulated lift, its nominal trial, as the animation "simulated". Throws
/// InvalidArgument ("trajectory") when the result has no trajectory.
std::string planGlb(const PlanningWorld& world, const PlanRequest& request,
                    const PlanResult& result);

/// Plans a grasp and a path to it; with request.goals, a path to one of
/// those goals instead (motion_goal.h, docs/planning.md "Motion-only
/// goals"; also InvalidArgument "goals[i]...", and "validate", which a
/// motion plan cannot). Single-threaded (kRrtConnect: two
/// threads, both joined before it returns); the same request and seed give
/// the same result unless the time limit cuts it short (kRrtConnect: see
/// LazyGoalRrtConnect::solve).
/// With the parameter `threads` = N > 1, N copies of the search race in N
/// threads, copy i with racingSeed(seed, i); the first to find a plan
/// wins, the others are stopped, and the result is the winner's (its seed
/// in PlanResult::seed). When none finds a plan the result is copy 0's
/// failure. Which copy wins depends on timing: racing trades the
/// determinism of one thread for the time to the first plan.
/// `cancel` (may be null) stops it from another thread. Throws
/// InvalidArgument naming the field ("start", "time_limit", "iterations",
/// "parameters.<name>") for a malformed request: a start of the wrong size,
/// not finite or outside the joint limits, a negative or non-finite time
/// limit, an unknown parameter or a value outside its range.
PlanResult planGrasp(const PlanningWorld& world, const PlanRequest& request,
                     const std::atomic<bool>* cancel = nullptr);

/// A successful plan's grasp checked again and simulated
/// (grasp_validation.h) with the request's planner parameters
/// (min_epsilon, max_penetration, final_resolution, friction) and
/// simulation options: what PlanRequest::validate adds to a result. A
/// pick and place with a trajectory is simulated whole too
/// (Validation::place: the grasp closed, lifted, carried, put down,
/// released, the object at rest; the rest check's limits judge the place).
/// Throws InvalidArgument ("plan") for a plan without a grasp: a failed
/// plan, or a motion plan (request.goals, or a robot without a hand).
Validation validatePlan(const PlanningWorld& world, const PlanRequest& request,
                        const PlanResult& plan);

/// Where the object is at each of the trajectory's points of a plan with a
/// lift: where it stood until the lift starts, then the palm's pose times
/// the grasp's transform (the object in the palm at the grasp), and with
/// a placement from the release on where it was put. Throws
/// InvalidArgument ("plan") for a plan without a lift or trajectory.
std::vector<Eigen::Isometry3d> objectAlongTrajectory(const PlanningWorld& world,
                                                     const PlanRequest& request,
                                                     const PlanResult& result);

/// A pick and place's motion after the closing, as the physics check
/// follows it: its lift and its trajectory from the lift's end. Throws
/// InvalidArgument ("plan") for a plan without a placement or trajectory.
physics::PlaceMotion placeMotion(const PlanResult& plan);

/// A pick and place simulated whole (physics::simulatePickAndPlace of its
/// placeMotion) with the request's simulation options: what
/// Validation::place holds. Throws InvalidArgument ("plan") as placeMotion.
physics::PlaceVerdict simulatePlace(const PlanningWorld& world, const PlanRequest& request,
                                    const PlanResult& plan);

}  // namespace hfts::planner
