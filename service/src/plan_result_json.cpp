#include "service/plan_result_json.h"

#include "json_geometry.h"
#include "service/validation_json.h"

namespace hfts::service {
namespace {

using nlohmann::json;

json contacts(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& normals) {
  json out = json::array();
  for (Eigen::Index i = 0; i < positions.cols(); ++i)
    out.push_back(
        {{"position", vectorJson(positions.col(i))}, {"normal", vectorJson(normals.col(i))}});
  return out;
}

json pointsJson(const Eigen::Matrix3Xd& points) {
  json out = json::array();
  for (Eigen::Index i = 0; i < points.cols(); ++i) out.push_back(vectorJson(points.col(i)));
  return out;
}

json graspJson(const planner::PlannedGrasp& g, const std::vector<std::string>& jointNames) {
  const auto fingers = static_cast<std::size_t>(g.contacts_world.cols());
  const auto handDofs = static_cast<std::size_t>(g.hand_configuration.size());
  return {{"node",
           {{"level", g.node.level},
            {"partitions",
             std::vector<std::uint32_t>(g.node.parts.begin(), g.node.parts.begin() + fingers)}}},
          {"contacts_world", contacts(g.contacts_world, g.inward_normals_world)},
          {"contacts_object", contacts(g.contacts_object, g.inward_normals_object)},
          {"normals", "inward"},
          {"epsilon", g.epsilon},
          {"penetration", g.penetration},
          {"planned_contacts_object", pointsJson(g.planned_contacts_object)},
          {"planned_epsilon", g.planned_epsilon},
          {"reachability", g.reachability},
          {"fingertip_error", g.fingertip_error},
          {"hand_joint_names",
           std::vector<std::string>(jointNames.end() - static_cast<std::ptrdiff_t>(handDofs),
                                    jointNames.end())},
          {"hand_configuration", vectorJson(g.hand_configuration)}};
}

/// Shaped like a ROS trajectory_msgs/JointTrajectory (time_from_start in
/// seconds), with the phases' times.
json trajectoryJson(const planner::GraspTrajectory& t, const std::vector<std::string>& jointNames) {
  json points = json::array();
  for (const planner::TrajectoryPoint& p : t.points)
    points.push_back({{"positions", vectorJson(p.positions)},
                      {"velocities", vectorJson(p.velocities)},
                      {"accelerations", vectorJson(p.accelerations)},
                      {"time_from_start", p.time}});
  return {{"joint_names", jointNames},        {"points", std::move(points)},
          {"duration", t.duration},           {"closing_start", t.closing_start},
          {"lift_start", t.lift_start},       {"carry_start", t.carry_start},
          {"place_start", t.place_start},     {"release_start", t.release_start},
          {"retreat_start", t.retreat_start}, {"deviation", t.deviation}};
}

json pathJson(const std::vector<Eigen::VectorXd>& path) {
  json out = json::array();
  for (const Eigen::VectorXd& q : path) out.push_back(vectorJson(q));
  return out;
}

json placementJson(const planner::Placement& p) {
  return {{"object_pose", poseJson(p.object_pose)},
          {"face_normal", vectorJson(p.face_normal)},
          {"tipping_angle", p.tipping_angle},
          {"carry", pathJson(p.carry)},
          {"descent", pathJson(p.descent)},
          {"open", vectorJson(p.open)},
          {"retreat", pathJson(p.retreat)},
          {"retreat_direction", p.retreat_direction},
          {"rest",
           {{"stable", p.rest.stable},
            {"displacement", p.rest.displacement},
            {"rotation", p.rest.rotation}}}};
}

json placeRejectedJson(const planner::PlaceRejections& r) {
  return {{"unsupported", r.unsupported},
          {"no_arm_ik", r.no_arm_ik},
          {"colliding", r.colliding},
          {"descent_blocked", r.descent_blocked},
          {"release_blocked", r.release_blocked},
          {"retreat_blocked", r.retreat_blocked},
          {"unstable", r.unstable}};
}

json exploredJson(const std::vector<planner::ExploredNode>& nodes) {
  json out = json::array();
  for (const planner::ExploredNode& n : nodes) {
    out.push_back({{"level", n.level},
                   {"contacts_object", pointsJson(n.contacts_object)},
                   {"value", n.value},
                   {"epsilon", n.quality},
                   {"goal", n.goal}});
  }
  return out;
}

json statsJson(const planner::PlanStatistics& s) {
  json out = json::object();
  planner::forEachStatistic(s, [&out](const char* name, auto value) { out[name] = value; });
  return out;
}

}  // namespace

json planResultToJson(const planner::PlanResult& result, const planner::PlanRequest& request) {
  json path = json::array();
  for (const Eigen::VectorXd& q : result.path) path.push_back(vectorJson(q));
  const bool coupled = request.algorithm == planner::PlanAlgorithm::kCoupled;
  const bool paper = coupled && request.preset == planner::PlannerPreset::kPaper;
  const bool rrtConnect = request.algorithm == planner::PlanAlgorithm::kRrtConnect;
  json out = {{"success", result.success},
              {"reason", planner::toString(result.failure)},
              {"message", result.message},
              {"scene", request.scene.name},
              {"object", request.object},
              {"object_pose", poseJson(result.object_pose)},
              {"algorithm", paper        ? "paper"
                            : coupled    ? "coupled"
                            : rrtConnect ? "rrtconnect"
                                         : "decoupled"},
              {"seed", request.seed},
              {"plan_seed", result.seed},
              {"time_limit", request.time_limit},
              {"joint_names", result.joint_names},
              {"path", std::move(path)},
              {"clearance", result.clearance ? json(*result.clearance) : json()},
              {"grasp", result.success && request.goals.empty()
                            ? graspJson(result.grasp, result.joint_names)
                            : json()},
              {"trajectory", result.trajectory.points.empty()
                                 ? json()
                                 : trajectoryJson(result.trajectory, result.joint_names)},
              {"stats", statsJson(result.stats)}};
  if (!request.goals.empty())
    out["reached_goal"] = result.reached_goal ? json(*result.reached_goal) : json();
  else if (result.lift)
    out["lift"] = {{"direction", result.lift->direction}, {"path", pathJson(result.lift->path)}};
  else
    out["lift"] = json();
  if (request.place) {
    out["place"] = result.place ? placementJson(*result.place) : json();
    out["place_rejected"] = placeRejectedJson(result.place_rejected);
  }
  if (request.explored) out["explored"] = exploredJson(result.explored);
  if (result.validation) {
    out["validation"] = graspCheckToJson(result.validation->check);
    if (result.validation->physics)
      out["physics"] = physicsToJson(*result.validation->physics, /*motion=*/true);
    if (result.validation->place)
      out["place_physics"] = placePhysicsToJson(*result.validation->place);
  }
  return out;
}

}  // namespace hfts::service
