#include "service/catalog_json.h"

#include <nlohmann/json.hpp>

#include "grasp/grasp_quality_json.h"
#include "json_fields.h"
#include "json_geometry.h"
#include "service/rpc_error.h"

namespace hfts::service {
namespace {

using nlohmann::json;

const char* typeName(robot::Obstacle::Type type) {
  switch (type) {
    case robot::Obstacle::Type::kBox:
      return "box";
    case robot::Obstacle::Type::kCylinder:
      return "cylinder";
    case robot::Obstacle::Type::kSphere:
      return "sphere";
    case robot::Obstacle::Type::kMesh:
      return "mesh";
    case robot::Obstacle::Type::kPoints:
      return "points";
  }
  return "unknown";
}

json graspabilityJson(const grasp::Graspability& g) {
  return {{"fraction", g.fraction()},
          {"sampled", g.sampled},
          {"stable", g.stable},
          {"reachable", g.reachable}};
}

}  // namespace

json robotJson(const robot::RobotModel& robot) {
  const std::vector<std::string>& names = robot.dofNames();
  const auto arm = names.begin() + robot.numArmDofs();
  json tips = json::array();
  for (const robot::Fingertip& f : robot.fingertips()) tips.push_back(f.name);
  return {{"name", robot.name()},
          {"joint_names", names},
          {"arm_joint_names", std::vector<std::string>(names.begin(), arm)},
          {"hand_joint_names", std::vector<std::string>(arm, names.end())},
          {"lower_limits", vectorJson(robot.lowerLimits())},
          {"upper_limits", vectorJson(robot.upperLimits())},
          {"max_velocities", vectorJson(robot.maxVelocities())},
          {"max_accelerations", vectorJson(robot.maxAccelerations())},
          {"home", vectorJson(robot.home())},
          {"fingertips", std::move(tips)}};
}

json plannerParametersJson(const CatalogRobot& robot) {
  json out = json::array();
  for (const planner::PlannerParameterInfo& p : robot.parameters)
    out.push_back({{"name", p.name}, {"default", p.default_value}, {"range", p.range}});
  return out;
}

json robotsJson(const PlanningCatalog& catalog) {
  json out = json::array();
  for (const CatalogRobot& r : catalog.robots()) {
    json robot = robotJson(r.model());
    robot["planner_parameters"] = plannerParametersJson(r);
    out.push_back(std::move(robot));
  }
  return out;
}

const CatalogRobot& requestedRobot(const json& params, const PlanningCatalog& catalog) {
  const JsonFields f(params, "");
  if (!f.has("robot")) return catalog.robots().front();
  const std::string name = f.name("robot");
  const CatalogRobot* robot = catalog.findRobot(name);
  if (robot == nullptr) {
    std::string known;
    for (const std::string& n : catalog.robotNames()) known += (known.empty() ? "" : ", ") + n;
    f.fail("robot", "unknown robot '" + name + "' (this server plans for: " + known + ")");
  }
  return *robot;
}

json objectsJson(const PlanningCatalog& catalog, const CatalogRobot& robot) {
  json objects = json::array();
  for (const std::string& name : catalog.world().objectNames()) {
    const db::ObjectDatabase& o = *catalog.world().object(name);
    std::vector<std::size_t> nodes;
    for (const auto& level : o.levels) nodes.push_back(level.size());
    objects.push_back({{"name", name},
                       {"contacts", o.numContacts()},
                       {"nodes_per_level", nodes},
                       {"center_of_mass", vectorJson(o.geometry.center_of_mass)},
                       {"rho", o.geometry.rho},
                       {"graspability", robot.graspability.count(name) > 0
                                            ? graspabilityJson(robot.graspability.at(name))
                                            : json()},
                       {"source_mesh", o.source_mesh}});
  }
  return {{"robot", robot.name()}, {"objects", std::move(objects)}, {"skipped", catalog.skipped()}};
}

json scenesJson(const PlanningCatalog& catalog, const CatalogRobot& robot) {
  json scenes = json::array();
  for (const auto& [name, scene] : catalog.scenes()) {
    json obstacles = json::array();
    for (const robot::Obstacle& o : scene.obstacles)
      obstacles.push_back({{"name", o.name}, {"type", typeName(o.type)}});
    const std::optional<Eigen::VectorXd> start = scene.startFor(robot.name());
    json placements = json::array();
    for (const robot::Placement& p : scene.placements)
      placements.push_back({{"name", p.name}, {"pose", poseJson(p.pose)}, {"rest_on", p.rest_on}});
    scenes.push_back({{"name", name},
                      {"description", scene.description},
                      {"target_object", scene.target_object},
                      {"target_pose", poseJson(scene.target_pose)},
                      {"target_rest_on", scene.target_rest_on},
                      {"placements", std::move(placements)},
                      {"obstacles", std::move(obstacles)},
                      {"start", start ? vectorJson(*start) : json()}});
  }
  return {{"robot", robot.name()}, {"scenes", std::move(scenes)}};
}

json graspQualityJson(const json& params, const PlanningCatalog& catalog) {
  const JsonFields f(params, "");
  f.allowOnly({"contacts", "normals", "center", "torque_scale", "friction", "cone_edges",
               "torsional_friction", "object"});
  json request = params;
  if (f.has("object")) {
    const std::string name = f.name("object");
    const db::ObjectDatabase* object = catalog.world().object(name);
    if (object == nullptr) f.fail("object", "unknown object '" + name + "'");
    request.erase("object");
    if (!request.contains("center"))
      request["center"] = vectorJson(object->geometry.center_of_mass);
    if (!request.contains("torque_scale")) request["torque_scale"] = object->geometry.rho;
  }
  try {
    const grasp::GraspQualityRequest r = grasp::graspQualityRequestFromJson(request.dump());
    return {{"epsilon", grasp::graspQuality(r).epsilon}};
  } catch (const InvalidArgument& e) {
    throw invalidParam(e);
  }
}

}  // namespace hfts::service
