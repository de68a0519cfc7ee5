#pragma once
// A plan's validation (planner/grasp_validation.h) as JSON: the `validation`
// and `physics` blocks of a plan result (docs/protocol.md) and what
// hfts-validate prints with --json.

#include <nlohmann/json_fwd.hpp>

#include "planner/grasp_validation.h"

namespace hfts::service {

/// {"valid", "problem", "pads_touch", "epsilon", "penetration", "clear",
/// "closing_difference"}: the geometric checks of the executed grasp.
nlohmann::json graspCheckToJson(const planner::GraspCheck& check);

/// {"held", "held_fraction", "mass", "density", "collision_shape",
/// "shape_fidelity", "lift_direction", "trials": [{"name", "held",
/// "failure", "max_displacement", "max_rotation", "fingers_in_contact",
/// "simulated_time"}]},
/// with `motion` also "motion": the nominal trial's object poses
/// [{"time", "phase", "pose"}] (for a viewer).
nlohmann::json physicsToJson(const physics::GraspVerdict& verdict, bool motion);

/// A pick and place simulated whole (physics::PlaceVerdict), with its
/// object's motion: a plan's "place_physics".
nlohmann::json placePhysicsToJson(const physics::PlaceVerdict& verdict);

/// What to validate of a plan result (the `plan` method's JSON, as
/// hfts-client --out saves it): its last two configurations of "path"
/// (numDofs() numbers each) and "object_pose", placed in `scene` (the
/// plan's scene, which the caller loads: the result names it) with
/// "object" (or the scene's target) as its target. Throws RpcError
/// (kInvalidParams) naming the field: a failed plan, a path of fewer than
/// two configurations, configurations of the wrong size.
planner::ValidationRequest validationRequestFromPlan(const nlohmann::json& plan, robot::Scene scene,
                                                     const robot::RobotModel& robot);

}  // namespace hfts::service
