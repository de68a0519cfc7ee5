#pragma once
// The params of the `plan` method as a planner request (docs/protocol.md).

#include <nlohmann/json_fwd.hpp>

#include "planner/grasp_motion_planner.h"
#include "service/planning_catalog.h"

namespace hfts::service {

/// What the server allows a plan request.
struct PlanLimits {
  /// s; a larger `time_limit` is capped to it, and it is the default.
  double max_time_limit = 60.0;
  /// The most racing copies (planner parameter `threads`) one plan may
  /// run: the server's planning workers, so a racing plan cannot take more
  /// cores than the server was given.
  int max_threads = 1;
};

/// Maps the params of a `plan` call onto a PlanRequest, checking every
/// field against the catalog and the robot it plans for (`robot`, a robot
/// name of the catalog, default its first; see requestedRobot): `scene` (a scene name or an inline
/// scene of primitives), `object`, `object_pose`, `start`, `time_limit`, `algorithm`, `iterations`,
/// `seed`, `parameters` and `trajectory_rate` (`gltf` and `format` are allowed: see planExtras).
/// The result always has `object` and `time_limit` set. Throws RpcError(kInvalidParams) whose
/// message and field name the offending member ("start[3]", "object_pose.orientation",
/// "parameters.p_max") for unknown fields and names, names with path characters, wrong types and
/// lengths, non-finite numbers, zero-norm quaternions and start configurations outside the joint
/// limits of that robot, and a numeric `threads` above limits.max_threads. Parameter values are
/// otherwise checked by planGrasp.
planner::PlanRequest planRequestFromJson(const nlohmann::json& params,
                                         const PlanningCatalog& catalog, const PlanLimits& limits);

/// What a plan call's result carries beyond the plan.
struct PlanExtras {
  /// `gltf` (default false): the plan as an animated binary glTF, base64
  /// (planner::planGlb), in the result's `gltf`.
  bool gltf = false;
  /// `format` "ros" (default "json"): the plan as ROS messages
  /// (ros_messages.h) in the result's `ros` as well.
  bool ros = false;
};

/// The plan call's `gltf` and `format`. Throws like planRequestFromJson
/// when `gltf` is not a boolean or `format` neither "json" nor "ros".
PlanExtras planExtras(const nlohmann::json& params);

}  // namespace hfts::service
