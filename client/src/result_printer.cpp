#include "result_printer.h"

#include <nlohmann/json.hpp>

#include <iomanip>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace hfts::client {

using nlohmann::json;

namespace {

std::string numbers(const json& values, int precision) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(precision) << "(";
  for (std::size_t i = 0; i < values.size(); ++i) s << (i ? ", " : "") << values[i].get<double>();
  s << ")";
  return s.str();
}

std::string names(const json& values) {
  std::string out;
  for (const json& v : values) out += (out.empty() ? "" : " ") + v.get<std::string>();
  return out;
}

void printGrasp(const json& grasp, std::ostream& out) {
  out << "grasp (the hand closed until its pads touch): epsilon "
      << grasp.at("epsilon").get<double>() << " at the contacts touched (planned "
      << grasp.at("planned_epsilon").get<double>() << "), penetration "
      << 1000.0 * grasp.at("penetration").get<double>() << " mm, reachability "
      << grasp.at("reachability").get<double>() << " m, planned fingertip error "
      << grasp.at("fingertip_error").get<double>() << " m, HFTS node on level "
      << grasp.at("node").at("level").get<int>() << "\n";
  int finger = 1;
  for (const json& c : grasp.at("contacts_world"))
    out << "  contact " << finger++ << ": position " << numbers(c.at("position"), 4)
        << " m, inward normal " << numbers(c.at("normal"), 3) << " (world frame)\n";
  out << "  hand (" << names(grasp.at("hand_joint_names"))
      << "): " << numbers(grasp.at("hand_configuration"), 3) << " (rad; m for sliding joints)\n";
}

void printStats(const json& s, std::ostream& out) {
  out << "stats: " << s.at("iterations").get<std::uint64_t>() << " iterations, "
      << s.at("goal_sampling_calls").get<std::uint64_t>() << " goal sampling calls ("
      << s.at("valid_goal_samples").get<std::uint64_t>() << " valid), "
      << s.at("hfts_nodes_explored").get<std::uint64_t>() << " HFTS nodes, "
      << s.at("collision_checks").get<std::uint64_t>() << " collision checks, trees: forward "
      << s.at("forward_tree_size").get<std::uint64_t>() << " nodes, backward "
      << s.at("backward_tree_nodes").get<std::uint64_t>() << " nodes in "
      << s.at("goal_trees").get<std::uint64_t>() << " goal and "
      << s.at("approximate_trees").get<std::uint64_t>() << " approximate trees\n";
}

}  // namespace

void printInfo(const json& info, std::ostream& out) {
  const json& robot = info.at("robot");
  const json& limits = info.at("limits");
  const json& load = info.at("load");
  out << info.at("name").get<std::string>() << " " << info.at("version").get<std::string>() << " ("
      << info.at("protocol").get<std::string>() << ")\n";
  // Servers before several robots list only "robot".
  const json robots = info.contains("robots") ? info.at("robots") : json::array({robot});
  for (std::size_t i = 0; i < robots.size(); ++i)
    out << "robot: " << robots[i].at("name").get<std::string>() << ", "
        << robots[i].at("joint_names").size() << " DoF, " << robots[i].at("fingertips").size()
        << " fingertips" << (robots.size() > 1 && i == 0 ? " (the default)" : "") << ": "
        << names(robots[i].at("joint_names")) << "\n";
  out << "objects: " << info.at("objects").get<int>()
      << ", scenes: " << info.at("scenes").get<int>() << "\n"
      << "workers: " << load.at("workers").get<int>() << " (" << load.at("running").get<int>()
      << " planning, " << load.at("queued").get<int>() << " queued, queue capacity "
      << limits.at("queue_capacity").get<int>() << ")\n"
      << "limits: time_limit <= " << limits.at("max_time_limit").get<double>()
      << " s, messages <= " << limits.at("max_message_bytes").get<std::uint64_t>() << " bytes\n";
}

void printObjects(const json& objects, std::ostream& out) {
  // Graspability: the share of sampled leaf grasps that are stable and
  // reachable for the robot's hand in free space.
  const std::string robot = objects.value("robot", std::string());
  out << std::left << std::setw(16) << "object" << std::right << std::setw(10) << "contacts"
      << "  nodes per level   rho (m)  graspable"
      << (robot.empty() ? std::string() : " (" + robot + ")") << "\n";
  for (const json& o : objects.at("objects")) {
    std::string levels;
    for (const json& n : o.at("nodes_per_level"))
      levels += (levels.empty() ? "" : "/") + std::to_string(n.get<int>());
    out << std::left << std::setw(16) << o.at("name").get<std::string>() << std::right
        << std::setw(10) << o.at("contacts").get<int>() << "  " << std::left << std::setw(16)
        << levels << std::right << std::fixed << std::setprecision(4) << std::setw(9)
        << o.at("rho").get<double>();
    if (o.contains("graspability") && o.at("graspability").is_object())
      out << std::setprecision(1) << std::setw(10)
          << 100.0 * o.at("graspability").at("fraction").get<double>() << " %";
    out << "\n";
  }
  out.unsetf(std::ios::floatfield);
  for (const json& why : objects.at("skipped"))
    out << "skipped: " << why.get<std::string>() << "\n";
}

void printScenes(const json& scenes, std::ostream& out) {
  for (const json& s : scenes.at("scenes"))
    out << std::left << std::setw(10) << s.at("name").get<std::string>() << " target "
        << std::setw(10) << s.at("target_object").get<std::string>() << " at "
        << numbers(s.at("target_pose").at("position"), 3) << ", " << s.at("obstacles").size()
        << " obstacles: " << s.at("description").get<std::string>() << "\n";
}

/// The validate block: the grasp checked again and its physics verdict.
void printPhysics(const json& validation, const json& physics, std::ostream& out) {
  int held = 0;
  for (const json& t : physics.at("trials")) held += t.at("held").get<bool>() ? 1 : 0;
  out << "physics: " << (physics.at("held").get<bool>() ? "held" : "NOT held") << " (held in "
      << held << " of " << physics.at("trials").size() << " trials; mass "
      << physics.at("mass").get<double>() << " kg, lift "
      << physics.at("lift_direction").get<std::string>() << ")";
  if (!validation.at("valid").get<bool>())
    out << "; the grasp as executed: " << validation.at("problem").get<std::string>();
  out << "\n";
  for (const json& t : physics.at("trials"))
    if (!t.at("held").get<bool>())
      out << "  " << t.at("name").get<std::string>() << ": " << t.at("failure").get<std::string>()
          << "\n";
}

void printPlan(const json& plan, std::ostream& out) {
  const json& stats = plan.at("stats");
  const std::string what =
      (plan.contains("robot") ? plan.at("robot").get<std::string>() + ", " : std::string()) +
      plan.at("scene").get<std::string>() + ", " +
      (plan.at("object").get<std::string>().empty() ? std::string()
                                                    : plan.at("object").get<std::string>() + ", ") +
      plan.at("algorithm").get<std::string>() + ", seed " + plan.at("seed").dump();
  out << std::setprecision(4);
  if (plan.at("success").get<bool>()) {
    out << "plan: success (" << what << ") in " << stats.at("planning_time").get<double>()
        << " s\n";
    const json& goal = plan.value("reached_goal", json());
    if (goal.is_number())
      out << "motion: reached goal " << goal.get<int>() << " of the request's\n";
    else
      printGrasp(plan.at("grasp"), out);
    out << "path: " << plan.at("path").size() << " waypoints ("
        << (goal.is_number() ? "start ... goal" : "start ... pre-grasp, grasp") << "), length "
        << stats.at("path_length_smoothed").get<double>() << " (Eq. 3 metric; "
        << stats.at("path_length_raw").get<double>() << " before smoothing)\n";
    if (const json& c = plan.value("clearance", json()); c.is_number())
      out << "path proven free (certify_path); the nearest distance its proofs measured: "
          << c.get<double>() * 1000 << " mm\n";
    if (const json& place = plan.value("place", json()); place.is_object())
      out << "place: on " << numbers(place.at("object_pose").at("position"), 3) << " after a "
          << place.at("carry").size() << "-waypoint carry, retreat "
          << place.at("retreat_direction").get<std::string>() << "; released alone there it "
          << (place.at("rest").at("stable").get<bool>() ? "stays" : "does NOT stay") << "\n";
    if (const json& t = plan.value("trajectory", json()); t.is_object()) {
      out << "trajectory: " << t.at("duration").get<double>() << " s, " << t.at("points").size()
          << " points";
      if (!goal.is_number())
        out << ", the hand closes from " << t.at("closing_start").get<double>() << " s";
      if (plan.value("place", json()).is_object())
        out << ", carries from " << t.at("carry_start").get<double>() << " s, opens from "
            << t.at("release_start").get<double>() << " s";
      out << "\n";
    }
    if (plan.contains("physics")) printPhysics(plan.at("validation"), plan.at("physics"), out);
    if (const json& p = plan.value("place_physics", json()); p.is_object())
      out << "pick and place in physics: "
          << (p.at("held").get<bool>() ? "held through the carry" : "NOT held through the carry")
          << ", " << (p.at("placed").get<bool>() ? "stayed where released" : "did NOT stay")
          << (p.at("failure").get<std::string>().empty()
                  ? std::string()
                  : " (" + p.at("failure").get<std::string>() + ")")
          << "\n";
  } else {
    out << "plan: no plan, " << plan.at("reason").get<std::string>() << ": "
        << plan.at("message").get<std::string>() << " (" << what << ") after "
        << stats.at("planning_time").get<double>() << " s\n";
  }
  printStats(stats, out);
}

void writeTrajectoryCsv(const json& plan, std::ostream& out) {
  const json& t = plan.value("trajectory", json());
  if (!t.is_object()) throw std::runtime_error("the plan has no trajectory");
  const auto names = t.at("joint_names").get<std::vector<std::string>>();
  out << "time_from_start";
  for (const char* suffix : {"", "_velocity", "_acceleration"})
    for (const std::string& name : names) out << "," << name << suffix;
  out << "\n" << std::setprecision(17);
  for (const json& p : t.at("points")) {
    out << p.at("time_from_start").get<double>();
    for (const char* field : {"positions", "velocities", "accelerations"})
      for (const json& v : p.at(field)) out << "," << v.get<double>();
    out << "\n";
  }
}

void printQuality(const json& quality, std::ostream& out) {
  out << "epsilon " << std::setprecision(10) << quality.at("epsilon").get<double>() << "\n";
}

}  // namespace hfts::client
