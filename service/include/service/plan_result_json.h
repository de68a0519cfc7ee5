#pragma once
// A planner result as the JSON result of the `plan` method (docs/protocol.md).

#include <nlohmann/json_fwd.hpp>

#include "planner/grasp_motion_planner.h"

namespace hfts::service {

/// {"success", "reason" (planner::toString of the failure, "none" on
/// success), "message", "joint_names", "path" (one array per waypoint,
/// start ... pre-grasp, grasp), "grasp" (null unless successful: node,
/// world- and object-frame contacts with inward normals, epsilon,
/// reachability, fingertip_error, hand_configuration, hand_joint_names),
/// "stats", and from the request "scene", "object", "object_pose" (the
/// one planned with), "algorithm", "seed", "time_limit"}. Poses and vectors follow the project's
/// conventions.
nlohmann::json planResultToJson(const planner::PlanResult& result,
                                const planner::PlanRequest& request);

}  // namespace hfts::service
