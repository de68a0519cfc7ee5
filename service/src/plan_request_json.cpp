#include "service/plan_request_json.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>

#include "json_fields.h"
#include "service/catalog_json.h"
#include "service/rpc_error.h"

namespace hfts::service {
namespace {

using nlohmann::json;

/// The most motion goals one request may give.
constexpr std::size_t kMaxGoals = 1000;

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

/// Refuses obstacles (the JSON array at `path`) that would make the server
/// read a file: a client never makes it read one. `whose` names them in
/// the message.
void refuseFiles(const json& obstacles, const std::string& path, const std::string& whose) {
  if (!obstacles.is_array()) return;  // the scene parser says what is wrong
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    const json& o = obstacles[i];
    if (!o.is_object()) continue;
    const std::string at = path + "[" + std::to_string(i) + "]";
    if (o.contains("type") && o["type"] == "mesh")
      throwInvalidParam(at, whose + " may not load mesh files (use box, cylinder or sphere)");
    for (const char* key : {"file", "mask"})
      if (o.contains(key))
        throwInvalidParam(at + "." + key,
                          whose +
                              " may not load files (give points inline, or a depth image as "
                              "png_base64 or npy_base64, and mask_base64)");
  }
}

robot::Scene inlineScene(const JsonFields& f, const PlanningCatalog& catalog) {
  const json& scene = f.at("scene");
  if (const auto obstacles = scene.find("obstacles"); obstacles != scene.end())
    refuseFiles(*obstacles, "scene.obstacles", "inline scenes");
  try {
    return robot::parseScene(scene.dump(), catalog.sceneDir(), "inline scene");
  } catch (const robot::SceneError& e) {
    f.fail(e.field().empty() ? "scene" : "scene." + e.field(), e.problem());
  }
}

/// `obstacles`: more obstacles in the scene file format, appended to the
/// scene's; like an inline scene's, they may not name files.
void appendObstacles(const JsonFields& f, const PlanningCatalog& catalog, robot::Scene& scene) {
  const json& obstacles = f.at("obstacles");
  if (!obstacles.is_array())
    f.fail("obstacles", "must be an array of obstacles in the scene file format");
  refuseFiles(obstacles, "obstacles", "a request's obstacles");
  // Before the parse, which may decode images.
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    const json& o = obstacles[i];
    if (o.is_object() && o.contains("name") && o["name"].is_string() &&
        scene.obstacle(o["name"].get<std::string>()) != nullptr)
      f.fail("obstacles[" + std::to_string(i) + "].name", "'" + o["name"].get<std::string>() +
                                                              "' is an obstacle of scene '" +
                                                              scene.name + "' already");
  }
  try {
    for (robot::Obstacle& o :
         robot::parseObstacles(obstacles.dump(), catalog.sceneDir(), "obstacles"))
      scene.obstacles.push_back(std::move(o));
  } catch (const robot::SceneError& e) {
    f.fail(e.field().empty() ? "obstacles" : e.field(), e.problem());
  }
}

robot::Scene sceneOf(const JsonFields& f, const PlanningCatalog& catalog) {
  if (f.at("scene").is_object()) return inlineScene(f, catalog);
  if (!f.at("scene").is_string()) f.fail("scene", "must be a scene name or an inline scene object");
  const std::string name = f.name("scene");
  const robot::Scene* scene = catalog.scene(name);
  if (scene == nullptr) {
    std::vector<std::string> known;
    for (const auto& entry : catalog.scenes()) known.push_back(entry.first);
    f.fail("scene", "unknown scene '" + name + "' (known: " + joined(known) + ")");
  }
  return *scene;
}

std::string objectOf(const JsonFields& f, const PlanningCatalog& catalog,
                     const robot::Scene& scene) {
  const std::string name = f.has("object") ? f.name("object") : scene.target_object;
  if (catalog.world().object(name) == nullptr)
    f.fail(f.has("object") ? "object" : "scene",
           "unknown object '" + name + "' (known: " + joined(catalog.world().objectNames()) + ")");
  return name;
}

void checkStart(const JsonFields& f, const robot::RobotModel& robot,
                const planner::PlanRequest& r) {
  const char* field = r.start ? "start" : "scene.start";
  const Eigen::VectorXd start =
      r.start ? *r.start : r.scene.startFor(robot.name()).value_or(robot.home());
  if (start.size() != robot.numDofs())
    f.fail(field, "must hold " + std::to_string(robot.numDofs()) + " values, got " +
                      std::to_string(start.size()));
  std::string why;
  if (!robot.withinLimits(start, 1e-9, &why)) f.fail(field, "outside the joint limits: " + why);
}

/// The `physics` object: options of the physics check that `validate` runs.
/// `lift`: true (the default lift), false (none) or {"height": metres,
/// "held_speed": fraction}.
std::optional<planner::LiftOptions> liftOf(const JsonFields& f) {
  const nlohmann::json& lift = f.at("lift");
  if (lift.is_boolean())
    return lift.get<bool>() ? std::optional(planner::LiftOptions{}) : std::nullopt;
  if (!lift.is_object())
    f.fail("lift", "must be true, false or {\"height\": metres, \"held_speed\": fraction}");
  const JsonFields l(lift, "lift");
  l.allowOnly({"height", "held_speed"});
  planner::LiftOptions o;
  if (l.has("height")) o.height = l.positive("height");
  if (l.has("held_speed")) o.held_speed = l.positive("held_speed");
  try {
    planner::checkLiftOptions(o);
  } catch (const InvalidArgument& e) {
    l.fail(e.field().substr(e.field().find('.') + 1), e.problem());
  }
  return o;
}

/// `place`: {"on": obstacle, "area": {"min": [x, y], "max": [x, y]},
/// "upright": bool, "search": "coupled" | "decoupled"}, the region checked
/// against the scene.
void placeOf(const JsonFields& f, planner::PlanRequest& r) {
  if (!f.at("place").is_object()) f.fail("place", "must be an object {\"on\": obstacle, ...}");
  const JsonFields p(f.at("place"), "place");
  p.allowOnly({"on", "area", "upright", "search"});
  planner::PlaceGoal goal;
  goal.on = p.string("on");
  if (p.has("area")) {
    if (!p.at("area").is_object()) p.fail("area", "must be {\"min\": [x, y], \"max\": [x, y]}");
    const JsonFields a(p.at("area"), "place.area");
    a.allowOnly({"min", "max"});
    const Eigen::VectorXd low = a.numbers("min", 2), high = a.numbers("max", 2);
    goal.area = Eigen::AlignedBox2d(low.head<2>(), high.head<2>());
  }
  if (p.has("upright")) goal.upright = p.boolean("upright");
  const std::string search = p.has("search") ? p.string("search") : "coupled";
  if (search == "decoupled")
    r.place_search = planner::PlaceSearch::kDecoupled;
  else if (search != "coupled")
    p.fail("search", "must be \"coupled\" (the default) or \"decoupled\", got \"" + search + "\"");
  try {
    planner::placeRegion(r.scene, goal);
  } catch (const InvalidArgument& e) {
    throwInvalidParam(e.field(), e.problem());
  }
  r.place = goal;
}

physics::SimulationOptions simulationOptionsOf(const JsonFields& f) {
  if (!f.at("physics").is_object()) f.fail("physics", "must be an object");
  const JsonFields p(f.at("physics"), "physics");
  p.allowOnly({"density", "friction", "perturb"});
  physics::SimulationOptions o;
  if (p.has("density")) o.density = p.positive("density");
  if (p.has("friction")) o.friction = p.finite("friction");
  if (p.has("perturb")) o.perturb = p.boolean("perturb");
  try {
    physics::validateOptions(o);
  } catch (const InvalidArgument& e) {
    p.fail(e.field().substr(e.field().find('.') + 1), e.problem());
  }
  return o;
}

std::map<std::string, std::string> parametersOf(const JsonFields& f, const CatalogRobot& robot) {
  const JsonFields p(f.at("parameters"), "parameters");
  std::map<std::string, std::string> out;
  for (const auto& item : f.at("parameters").items()) {
    const std::string& name = item.key();
    if (name == "time_limit" || name == "iterations")
      p.fail(name, "set it with the top-level '" + name + "' field");
    const auto& declared = robot.parameters;
    if (std::none_of(declared.begin(), declared.end(),
                     [&](const planner::PlannerParameterInfo& i) { return i.name == name; }))
      p.fail(name, "unknown planner parameter (see server.info)");
    const json& v = item.value();
    if (v.is_number_integer())
      out[name] = v.dump();
    else if (v.is_number())
      out[name] = json(p.finite(name.c_str())).dump();
    else if (v.is_string())
      out[name] = v.get<std::string>();
    else
      p.fail(name, "must be a number or a string");
  }
  return out;
}

/// One motion goal: {"joints": [...]} or {"pose": {...}, "link",
/// "position_tolerance", "orientation_tolerance"}.
planner::MotionGoal goalOf(const json& goal, const std::string& path) {
  if (!goal.is_object()) throwInvalidParam(path, "must be an object with \"joints\" or \"pose\"");
  const JsonFields g(goal, path);
  g.allowOnly({"joints", "pose", "link", "position_tolerance", "orientation_tolerance"});
  if (g.has("joints") == g.has("pose"))
    g.fail(g.has("joints") ? "pose" : "joints", "a goal has either \"joints\" or \"pose\"");
  if (g.has("joints")) {
    if (g.has("link") || g.has("position_tolerance") || g.has("orientation_tolerance"))
      g.fail("joints", "a joint goal takes no link or tolerances");
    const json& joints = g.at("joints");
    if (!joints.is_array()) g.fail("joints", "must be an array of joint values");
    return planner::JointGoal{g.numbers("joints", static_cast<Eigen::Index>(joints.size()))};
  }
  planner::PoseGoal pose;
  pose.pose = g.pose("pose");
  if (g.has("link")) pose.link = g.string("link");
  if (g.has("position_tolerance")) pose.position_tolerance = g.finite("position_tolerance");
  if (g.has("orientation_tolerance"))
    pose.orientation_tolerance = g.finite("orientation_tolerance");
  return pose;
}

/// `goal` (one) or `goals` (a non-empty array), checked for the robot.
std::vector<planner::MotionGoal> goalsOf(const JsonFields& f, const robot::RobotModel& robot,
                                         const planner::PlanRequest& r) {
  if (f.has("goal") && f.has("goals")) f.fail("goals", "give either \"goal\" or \"goals\"");
  std::vector<planner::MotionGoal> goals;
  if (f.has("goal")) {
    goals.push_back(goalOf(f.at("goal"), "goal"));
  } else {
    const json& all = f.at("goals");
    if (!all.is_array() || all.empty() || all.size() > kMaxGoals)
      f.fail("goals", "must be an array of 1 to " + std::to_string(kMaxGoals) + " goals");
    for (std::size_t i = 0; i < all.size(); ++i)
      goals.push_back(goalOf(all[i], "goals[" + std::to_string(i) + "]"));
  }
  try {
    planner::checkGoals(robot, goals, r.start ? *r.start : robot.home());
  } catch (const InvalidArgument& e) {
    // checkGoals names goals[i]; a single `goal` is goal.
    std::string field = e.field();
    if (f.has("goal")) field.replace(0, field.find(']') + 1, "goal");
    throwInvalidParam(field, e.problem());
  }
  return goals;
}

}  // namespace

PlanExtras planExtras(const json& params) {
  const JsonFields f(params, "");
  PlanExtras extras;
  extras.gltf = f.has("gltf") && f.boolean("gltf");
  if (f.has("format")) {
    const std::string format = f.string("format");
    if (format != "json" && format != "ros")
      f.fail("format", "must be \"json\" (the default) or \"ros\"");
    extras.ros = format == "ros";
  }
  return extras;
}

planner::PlanRequest planRequestFromJson(const json& params, const PlanningCatalog& catalog,
                                         const PlanLimits& limits) {
  const JsonFields f(params, "");
  f.allowOnly({"robot",           "scene",     "object",     "object_pose", "start",
               "time_limit",      "algorithm", "iterations", "seed",        "parameters",
               "trajectory_rate", "gltf",      "format",     "explored",    "validate",
               "physics",         "goal",      "goals",      "lift",        "place",
               "obstacles"});
  const CatalogRobot& planned = requestedRobot(params, catalog);
  const bool motion = f.has("goal") || f.has("goals");
  if (!motion && !planned.model().hasHand())
    f.fail("goals", "robot '" + planned.model().name() +
                        "' has no hand: it plans motions to a goal or goals only");
  planner::PlanRequest r;
  r.scene = sceneOf(f, catalog);
  if (f.has("obstacles")) appendObstacles(f, catalog, r.scene);
  // A motion plan needs no object: the scene's target, if it names one, is
  // an obstacle.
  if (!motion || f.has("object") || !r.scene.target_object.empty())
    r.object = objectOf(f, catalog, r.scene);
  if (f.has("object_pose")) r.object_pose = f.pose("object_pose");
  const robot::RobotModel& robot = planned.model();
  if (f.has("start")) {
    const json& start = f.at("start");
    if (start.is_array() && static_cast<Eigen::Index>(start.size()) != robot.numDofs())
      f.fail("start", "must hold " + std::to_string(robot.numDofs()) +
                          " values, one per joint of robot '" + robot.name() + "', got " +
                          std::to_string(start.size()));
    r.start = f.numbers("start", robot.numDofs());
  }
  checkStart(f, robot, r);
  if (motion) r.goals = goalsOf(f, robot, r);
  r.time_limit = std::min(f.has("time_limit") ? f.positive("time_limit") : limits.max_time_limit,
                          limits.max_time_limit);
  const std::string algorithm = f.has("algorithm") ? f.string("algorithm") : "coupled";
  if (algorithm == "decoupled") {
    r.algorithm = planner::PlanAlgorithm::kDecoupled;
  } else if (algorithm == "paper") {  // the coupled planner as the paper has it
    r.preset = planner::PlannerPreset::kPaper;
    r.lift.reset();  // the paper's plans end with the hand closed
  } else if (algorithm != "coupled") {
    f.fail("algorithm",
           "must be \"coupled\", \"paper\" or \"decoupled\", got \"" + algorithm + "\"");
  }
  if (f.has("iterations")) {
    if (r.algorithm != planner::PlanAlgorithm::kDecoupled)
      f.fail("iterations", "only the decoupled algorithm takes iterations");
    r.iterations = f.positiveInt("iterations");
  }
  if (f.has("seed")) r.seed = f.unsignedInteger("seed");
  if (f.has("explored")) r.explored = f.boolean("explored");
  if (f.has("validate")) r.validate = f.boolean("validate");
  if (motion && r.validate)
    f.fail("validate", "a motion plan (goal, goals) has no grasp to validate");
  if (f.has("physics")) r.simulation = simulationOptionsOf(f);
  if (f.has("lift")) {
    if (motion) f.fail("lift", "a motion plan (goal, goals) holds no object to lift");
    r.lift = liftOf(f);
  }
  if (f.has("place")) {
    if (motion) f.fail("place", "a motion plan (goal, goals) holds no object to place");
    if (!r.lift) f.fail("place", "a pick and place lifts the object first: the lift must be on");
    placeOf(f, r);
  }
  if (f.has("trajectory_rate")) {
    r.trajectory_rate = f.finite("trajectory_rate");
    if (!(r.trajectory_rate >= 0.0 && r.trajectory_rate <= planner::kMaxTrajectoryRate))
      f.fail("trajectory_rate", "must be in [0, 1000] samples per second (0: no trajectory)");
  }
  if (f.has("parameters")) r.parameters = parametersOf(f, planned);
  // Every value checked now, as planGrasp will read them, and the race
  // within this server's workers.
  int threads = 1;
  try {
    threads = planner::resolveSettings(planned.model(), r).execution.threads;
  } catch (const InvalidArgument& e) {
    throwInvalidParam(e.field(), e.problem());
  }
  if (threads > limits.max_threads)
    throwInvalidParam("parameters.threads", "at most " + std::to_string(limits.max_threads) +
                                                " on this server (its planning workers), got " +
                                                std::to_string(threads));
  return r;
}

}  // namespace hfts::service
