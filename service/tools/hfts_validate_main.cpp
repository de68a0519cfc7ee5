// hfts-validate: does a plan's grasp hold? Reads a plan result (the `plan`
// method's JSON, e.g. hfts-client plan --out PLAN.json), closes the hand
// again from the plan's pre-grasp, checks the grasp as executed
// (docs/planning.md#what-a-goal-is) and simulates it in MuJoCo
// (docs/physics.md). Exit status 0 when it holds, 1 when it does not, 2 for
// bad input.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <string>

#include "planner/grasp_motion_planner.h"
#include "planner/planning_world.h"
#include "robot/scene.h"
#include "service/rpc_error.h"
#include "service/validation_json.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Options {
  std::string plan, robot, robotsDir = "robots", db = "build/databases", scene,
                           sceneDir = "objects/scenes";
  std::optional<double> minEpsilon, maxPenetration, density, friction;
  bool noPhysics = false, nominalOnly = false, asJson = false;
};

json readPlan(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read plan '" + path + "'");
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw std::runtime_error("plan '" + path + "' is not JSON: " + e.what());
  }
}

/// The plan's string member `key`, or `fallback` when it has none.
std::string member(const json& plan, const char* key, const std::string& fallback) {
  const auto it = plan.find(key);
  return it != plan.end() && it->is_string() && !it->get<std::string>().empty()
             ? it->get<std::string>()
             : fallback;
}

/// A planner parameter's value for this robot: its default unless given.
double parameter(const hfts::planner::PlanningWorld& world, const std::string& name,
                 const std::optional<double>& given) {
  if (given) return *given;
  for (const auto& p : hfts::planner::plannerParameters(world))
    if (p.name == name) return std::stod(p.default_value);
  throw std::logic_error("no planner parameter '" + name + "'");
}

void printText(const hfts::planner::Validation& v, const hfts::planner::ValidationRequest& r) {
  const hfts::planner::GraspCheck& c = v.check;
  std::cout << std::setprecision(3)
            << "grasp as executed: " << (c.valid() ? "valid" : "NOT valid: " + c.problem) << "\n"
            << "  every pad on the object: " << (c.pads_touch ? "yes" : "no")
            << " (the hand closes " << c.closing_difference
            << " rad or m beyond the plan's grasp), epsilon " << c.epsilon << " (min "
            << r.check.min_epsilon << "), penetration " << 1000.0 * c.penetration << " mm (max "
            << 1000.0 * r.check.max_penetration << " mm), " << (c.clear ? "clear" : "colliding")
            << "\n";
  if (c.load_capacity)
    std::cout << "  load capacity " << *c.load_capacity
              << " (times the weight and disturbances the rated efforts can hold)\n";
  if (!v.physics) return;
  const hfts::physics::GraspVerdict& p = *v.physics;
  int held = 0;
  for (const auto& t : p.trials) held += t.held;
  std::cout << "physics: " << (p.held ? "HELD" : "NOT held") << " (held in " << held << " of "
            << p.trials.size() << " trials, at least "
            << std::ceil(r.simulation.min_held_fraction * static_cast<double>(p.trials.size()) -
                         1e-9)
            << " needed; mass " << p.mass << " kg at " << p.density << " kg/m^3, the object as its "
            << p.collision_shape << ", lift " << p.lift_direction << ")\n";
  for (const auto& t : p.trials)
    std::cout << "  " << std::left << std::setw(14) << t.name << std::right
              << (t.held ? "held" : "dropped") << ", largest slip " << 1000.0 * t.max_displacement
              << " mm, turn " << t.max_rotation * 180.0 / M_PI << " deg, " << t.fingers_in_contact
              << " fingers in contact" << (t.failure.empty() ? "" : ": " + t.failure) << "\n";
}

int run(const Options& o) {
  const json plan = readPlan(o.plan);
  const std::string robotName = member(plan, "robot", "kr5_sdh");
  const fs::path robotConfig = o.robot.empty()
                                   ? fs::path(o.robotsDir) / robotName / (robotName + ".json")
                                   : fs::path(o.robot);
  const auto world = hfts::planner::PlanningWorld::load(robotConfig, o.db);
  const fs::path sceneFile = o.scene.empty()
                                 ? fs::path(o.sceneDir) / (member(plan, "scene", "") + ".json")
                                 : fs::path(o.scene);
  hfts::planner::ValidationRequest r = hfts::service::validationRequestFromPlan(
      plan, hfts::robot::loadScene(sceneFile), world->robot());
  r.check.min_epsilon = parameter(*world, "min_epsilon", o.minEpsilon);
  r.check.max_penetration = parameter(*world, "max_penetration", o.maxPenetration);
  r.check.resolution = parameter(*world, "final_resolution", std::nullopt);
  r.check.friction = parameter(*world, "friction", o.friction);
  r.physics = !o.noPhysics;
  r.simulation.density = o.density;
  if (o.friction) r.simulation.friction = *o.friction;
  r.simulation.perturb = !o.nominalOnly;
  const hfts::planner::Validation v = hfts::planner::validateGrasp(*world, r);
  if (o.asJson) {
    json out = {{"holds", v.holds()}, {"validation", hfts::service::graspCheckToJson(v.check)}};
    if (v.physics) out["physics"] = hfts::service::physicsToJson(*v.physics, false);
    std::cout << out.dump(2) << "\n";
  } else {
    printText(v, r);
  }
  return v.holds() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{
      "hfts-validate: does a plan's grasp hold? Closes the hand again from the plan's "
      "pre-grasp, checks the grasp as executed and simulates it (exit status 0: it holds, 1: "
      "it does not, 2: bad input)"};
  app.add_option("plan", o.plan, "Plan result (JSON, e.g. hfts-client plan --out)")->required();
  app.add_option("--robot", o.robot,
                 "Robot config (default: ROBOTS_DIR/R/R.json for the plan's \"robot\" R)");
  app.add_option("--robots-dir", o.robotsDir, "Where the bundled robots are")
      ->capture_default_str();
  app.add_option("--db", o.db, "Object databases and hand maps")->capture_default_str();
  app.add_option("--scene", o.scene,
                 "Scene file (default: SCENE_DIR/S.json for the plan's \"scene\" S)");
  app.add_option("--scene-dir", o.sceneDir, "Where named scenes are")->capture_default_str();
  app.add_option("--min-epsilon", o.minEpsilon, "Smallest epsilon (default: the robot's)")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--max-penetration", o.maxPenetration,
                 "Deepest fingertip in the object, m (default: the robot's)")
      ->check(CLI::Range(0.0, 0.01));
  app.add_option("--density", o.density, "Object density, kg/m^3 (default: the database's)")
      ->check(CLI::Range(10.0, 25000.0));
  app.add_option("--friction", o.friction, "Friction coefficient (default: the planner's)")
      ->check(CLI::Range(1e-6, 10.0));
  app.add_flag("--no-physics", o.noPhysics, "Only the geometric checks");
  app.add_flag("--nominal-only", o.nominalOnly, "One physics trial, no perturbations");
  app.add_flag("--json", o.asJson, "Print the verdict as JSON");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    return run(o);
  } catch (const hfts::service::RpcError& e) {
    std::cerr << "hfts-validate: " << o.plan << ": " << e.what() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "hfts-validate: " << e.what() << "\n";
  }
  return 2;
}
