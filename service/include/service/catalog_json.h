#pragma once
// The read-only methods of the service as JSON: what the catalog holds
// (robot, objects, scenes, planner parameters) and grasp quality.

#include <nlohmann/json_fwd.hpp>

#include "service/planning_catalog.h"

namespace hfts::service {

/// {"name", "joint_names", "arm_joint_names", "hand_joint_names",
/// "lower_limits", "upper_limits", "home", "fingertips"}.
nlohmann::json robotJson(const robot::RobotModel& robot);

/// [{"name", "default", "range"}, ...], the parameters a plan for this
/// robot may set (some defaults depend on the robot).
nlohmann::json plannerParametersJson(const CatalogRobot& robot);

/// [robotJson + {"planner_parameters"}, ...], every robot of the catalog,
/// the default first.
nlohmann::json robotsJson(const PlanningCatalog& catalog);

/// The robot a call's params name in "robot" (a robot name); the catalog's
/// first when there is none. Throws RpcError(kInvalidParams) naming
/// "robot" and the known robots for an unknown one.
const CatalogRobot& requestedRobot(const nlohmann::json& params, const PlanningCatalog& catalog);

/// Result of `objects.list`: {"robot", "objects": [{"name", "contacts",
/// "nodes_per_level", "center_of_mass", "rho", "graspability",
/// "source_mesh"}], "skipped"}; graspability is for `robot`'s hand.
nlohmann::json objectsJson(const PlanningCatalog& catalog, const CatalogRobot& robot);

/// Result of `scenes.list`: {"robot", "scenes": [{"name", "description",
/// "target_object", "target_pose", "obstacles": [{"name", "type"}],
/// "start"}]}; "start" is the scene's start for `robot`, null when that
/// robot starts at its home.
nlohmann::json scenesJson(const PlanningCatalog& catalog, const CatalogRobot& robot);

/// Result of `grasp.quality`: {"epsilon"}. The params are those of
/// hfts-quality (docs/grasp_quality.md); with "object" (a database name)
/// the centre and torque scale default to the object's centre of mass and
/// rho, so contacts are given in the object frame. Throws
/// RpcError(kInvalidParams) naming the field.
nlohmann::json graspQualityJson(const nlohmann::json& params, const PlanningCatalog& catalog);

}  // namespace hfts::service
