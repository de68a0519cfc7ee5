// hfts-client: the planning service from the command line (docs/protocol.md).
// Subcommands info, objects, scenes, plan, quality, shutdown, and view (a
// saved plan as an HTML page; no server). Prints a human-readable summary,
// or the raw result with --json; --out FILE saves the result (JSON), plan
// --trajectory-csv / --gltf / --ros FILE its trajectory, animation and ROS
// messages; plan --depth FILE --camera JSON [--mask FILE] sends what a depth
// camera saw as the request's obstacles; --retries N connects and sends
// again when the connection fails before the answer (a balancer's instance
// died); --token-file FILE (or HFTS_TOKEN) authenticates to a server with
// tokens; --tls [--ca-file FILE] speaks TLS. Exit codes: 0 done, 1 a usage
// error, or the server or the connection failed (message on standard
// error), 3 the plan found no solution.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "client/plan_page.h"
#include "client/rpc_client.h"
#include "core/atomic_file.h"
#include "core/base64.h"
#include "depth_view.h"
#include "result_printer.h"

namespace {

using nlohmann::json;

struct Options {
  std::string host = "127.0.0.1";
  std::uint16_t port = 7450;
  bool json = false;
  std::string out;
  int retries = 2;
  std::string token_file;
  bool tls = false;
  std::string ca_file;
};

struct PlanOptions {
  std::string robot, scene, scene_file, object, algorithm;
  std::vector<double> object_pose, start;
  /// Motion goals: each a comma-separated list (joints, or x,y,z,qx,qy,qz,qw).
  std::vector<std::string> goal_joints, goal_poses;
  std::string goal_link;
  std::vector<double> goal_tolerance;
  std::vector<std::string> parameters;
  double time_limit = 0.0, trajectory_rate = 0.0;
  std::string trajectory_csv, gltf, ros;
  int iterations = 0;
  bool explored = false;
  bool validate = false;
  std::uint64_t seed = 1;
  /// Pick and place: the support to place on, its area, upright, the search.
  std::string place, place_search;
  std::vector<double> place_area;
  bool place_upright = false;
  /// What a depth camera sees, sent as the request's obstacles.
  std::string depth, camera, mask;
};

struct QualityOptions {
  std::string file, object;
};

struct ViewOptions {
  std::string plan, output, glb, viewer_dir = HFTS_VIEWER_DIR;
};

std::string readBinaryFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read '" + path + "'");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

json readJsonFile(const std::string& path) {
  std::string text;
  if (path == "-") {
    std::ostringstream in;
    in << std::cin.rdbuf();
    text = in.str();
  } else {
    text = readBinaryFile(path);
  }
  try {
    return json::parse(text);
  } catch (const json::exception& e) {
    throw std::runtime_error("'" + path + "' is not valid JSON: " + e.what());
  }
}

/// `view`: the plan's page, written next to nothing but `output`.
int writeView(const ViewOptions& v) {
  const json plan = readJsonFile(v.plan);
  const std::string glb = v.glb.empty() ? std::string() : readBinaryFile(v.glb);
  const std::string output = v.output.empty()
                                 ? std::filesystem::path(v.plan).replace_extension(".html").string()
                                 : v.output;
  hfts::core::writeFileAtomically(output, hfts::client::planPage(plan, glb, v.viewer_dir));
  std::cout << "wrote " << output << ": open it in a web browser (no server needed)\n";
  return 0;
}

/// "name=value": a number when the value reads as one, else text.
void addParameter(json& parameters, const std::string& assignment) {
  const std::size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw std::runtime_error("--param expects NAME=VALUE, got '" + assignment + "'");
  const std::string value = assignment.substr(eq + 1);
  std::istringstream in(value);
  double number = 0.0;
  in >> number;
  parameters[assignment.substr(0, eq)] =
      !value.empty() && in.eof() && !in.fail() ? json(number) : json(value);
}

/// "a,b,c" as numbers; `what` names the option in errors.
std::vector<double> numbersOf(const std::string& text, const std::string& what) {
  std::vector<double> out;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::istringstream number(item);
    double v = 0.0;
    number >> v;
    if (item.empty() || number.fail() || !number.eof())
      throw std::runtime_error(what + ": '" + item + "' is not a number");
    out.push_back(v);
  }
  return out;
}

/// The request's motion goals from --goal-joints / --goal-pose (none: a
/// grasp plan).
json goalsOf(const PlanOptions& p) {
  json goals = json::array();
  for (const std::string& joints : p.goal_joints)
    goals.push_back({{"joints", numbersOf(joints, "--goal-joints")}});
  for (const std::string& text : p.goal_poses) {
    const std::vector<double> v = numbersOf(text, "--goal-pose");
    if (v.size() != 7) throw std::runtime_error("--goal-pose expects x,y,z,qx,qy,qz,qw");
    json goal = {
        {"pose", {{"position", {v[0], v[1], v[2]}}, {"orientation", {v[3], v[4], v[5], v[6]}}}}};
    if (!p.goal_link.empty()) goal["link"] = p.goal_link;
    if (!p.goal_tolerance.empty()) {
      goal["position_tolerance"] = p.goal_tolerance[0];
      goal["orientation_tolerance"] = p.goal_tolerance[1];
    }
    goals.push_back(std::move(goal));
  }
  return goals;
}

/// The request's obstacles from --depth, --camera and --mask (null: none).
json obstaclesOf(const PlanOptions& p) {
  if (p.depth.empty() && p.camera.empty() && p.mask.empty()) return nullptr;
  if (p.depth.empty())
    throw std::runtime_error(p.camera.empty() ? "--mask needs --depth and --camera"
                                              : "--camera needs --depth (the image it took)");
  if (p.camera.empty())
    throw std::runtime_error("--depth needs --camera (a JSON file with its intrinsics and pose)");
  return json::array({hfts::client::depthView(p.depth, p.camera, p.mask)});
}

json planParams(const PlanOptions& p, const CLI::App& cmd) {
  json params = {{"seed", p.seed}};
  if (!p.robot.empty()) params["robot"] = p.robot;
  params["scene"] = p.scene_file.empty() ? json(p.scene) : readJsonFile(p.scene_file);
  if (!p.object.empty()) params["object"] = p.object;
  if (!p.object_pose.empty())
    params["object_pose"] = {
        {"position", {p.object_pose[0], p.object_pose[1], p.object_pose[2]}},
        {"orientation", {p.object_pose[3], p.object_pose[4], p.object_pose[5], p.object_pose[6]}}};
  if (!p.start.empty()) params["start"] = p.start;
  if (json obstacles = obstaclesOf(p); !obstacles.is_null())
    params["obstacles"] = std::move(obstacles);
  if (json goals = goalsOf(p); !goals.empty()) params["goals"] = std::move(goals);
  if (cmd.count("--time-limit")) params["time_limit"] = p.time_limit;
  if (!p.algorithm.empty()) params["algorithm"] = p.algorithm;
  if (cmd.count("--iterations")) params["iterations"] = p.iterations;
  if (cmd.count("--trajectory-rate")) params["trajectory_rate"] = p.trajectory_rate;
  if (!p.gltf.empty()) params["gltf"] = true;
  if (!p.ros.empty()) params["format"] = "ros";
  if (p.explored) params["explored"] = true;
  if (p.validate) params["validate"] = true;
  if (!p.place.empty()) {
    json place = {{"on", p.place}};
    if (!p.place_area.empty())
      place["area"] = {{"min", {p.place_area[0], p.place_area[1]}},
                       {"max", {p.place_area[2], p.place_area[3]}}};
    if (p.place_upright) place["upright"] = true;
    if (!p.place_search.empty()) place["search"] = p.place_search;
    params["place"] = std::move(place);
  }
  if (!p.parameters.empty()) {
    params["parameters"] = json::object();
    for (const std::string& a : p.parameters) addParameter(params["parameters"], a);
  }
  return params;
}

void addRobotOption(CLI::App& cmd, std::string& robot) {
  cmd.add_option("--robot", robot, "A robot of the server (info lists them; default its first)");
}

void addPlanOptions(CLI::App& cmd, PlanOptions& p) {
  addRobotOption(cmd, p.robot);
  auto* scene = cmd.add_option("--scene", p.scene, "A scene of the server (scenes lists them)");
  cmd.add_option("--scene-file", p.scene_file, "An inline scene: a scene file of primitives")
      ->check(CLI::ExistingFile)
      ->excludes(scene);
  cmd.add_option("--object", p.object, "Object database (default: the scene's target)");
  cmd.add_option("--object-pose", p.object_pose, "x,y,z,qx,qy,qz,qw (default: the scene's)")
      ->delimiter(',')
      ->expected(7);
  cmd.add_option("--start", p.start,
                 "Start configuration, one value per robot DoF (default: the scene's)")
      ->delimiter(',');
  cmd.add_option("--goal-joints", p.goal_joints,
                 "Plan a motion to this configuration instead of a grasp: every DoF or the "
                 "arm's, comma-separated (repeatable; the first goal reached ends the plan)");
  cmd.add_option("--goal-pose", p.goal_poses,
                 "Plan a motion that puts the palm (or --goal-link) at x,y,z,qx,qy,qz,qw in the "
                 "world frame (repeatable)");
  cmd.add_option("--goal-link", p.goal_link, "--goal-pose's link: the flange or the palm link");
  cmd.add_option("--goal-tolerance", p.goal_tolerance,
                 "--goal-pose's tolerances: metres,radians (server default 0.001,0.01)")
      ->delimiter(',')
      ->expected(2);
  cmd.add_option("--time-limit", p.time_limit, "Seconds (default and maximum: the server's)");
  cmd.add_option("--algorithm", p.algorithm,
                 "coupled (default), paper (the paper's settings) or decoupled");
  cmd.add_option("--iterations", p.iterations, "Decoupled: iterations per level");
  cmd.add_option("--seed", p.seed, "Random seed")->capture_default_str();
  cmd.add_option("--param", p.parameters, "Planner parameter NAME=VALUE (repeatable)");
  cmd.add_option("--trajectory-rate", p.trajectory_rate,
                 "Trajectory samples per second (server default 100; 0: none)");
  cmd.add_option("--trajectory-csv", p.trajectory_csv, "Write the plan's trajectory as CSV to FILE")
      ->type_name("FILE");
  cmd.add_flag("--explored", p.explored,
               "Include the HFTS nodes the goal sampler visited (coupled; the viewer draws them)");
  cmd.add_flag("--validate", p.validate,
               "Check the grasp as executed again and simulate it: does it hold? (seconds)");
  auto* place = cmd.add_option("--place", p.place,
                               "Pick and place: put the object down on this obstacle's top "
                               "(docs/placement.md)");
  cmd.add_option("--place-area", p.place_area, "With --place: x_min,y_min,x_max,y_max (world)")
      ->delimiter(',')
      ->expected(4)
      ->needs(place);
  cmd.add_flag("--place-upright", p.place_upright, "With --place: stand the object upright")
      ->needs(place);
  cmd.add_option("--place-search", p.place_search, "With --place: coupled (default) or decoupled")
      ->needs(place);
  cmd.add_option("--depth", p.depth,
                 "What a depth camera saw, as an obstacle: a 16-bit PNG (units mm unless "
                 "--camera says) or a float32 .npy (m), sent inline; needs --camera")
      ->type_name("FILE");
  cmd.add_option("--camera", p.camera,
                 "With --depth: JSON object with the camera's intrinsics {fx, fy, cx, cy} and "
                 "pose, and optionally name, units, min_depth, max_depth, voxel, radius, shadow, "
                 "outliers (docs/point_clouds.md)")
      ->type_name("JSON");
  cmd.add_option("--mask", p.mask,
                 "With --depth: an 8-bit PNG of the image's size, not 0 on the object to pick")
      ->type_name("FILE");
  cmd.add_option("--gltf", p.gltf, "Write the plan as an animated binary glTF to FILE (.glb)")
      ->type_name("FILE");
  cmd.add_option("--ros", p.ros,
                 "Write the plan as ROS messages to FILE (JSON: moveit_msgs/Grasp and "
                 "trajectory_msgs/JointTrajectory, docs/protocol.md)")
      ->type_name("FILE");
}

int output(const Options& o, const std::string& method, const json& result) {
  if (!o.out.empty()) hfts::core::writeFileAtomically(o.out, result.dump(2) + "\n");
  if (o.json) {
    std::cout << result.dump(2) << "\n";
  } else if (method == "server.info") {
    hfts::client::printInfo(result, std::cout);
  } else if (method == "objects.list") {
    hfts::client::printObjects(result, std::cout);
  } else if (method == "scenes.list") {
    hfts::client::printScenes(result, std::cout);
  } else if (method == "plan") {
    hfts::client::printPlan(result, std::cout);
  } else if (method == "grasp.quality") {
    hfts::client::printQuality(result, std::cout);
  } else if (method == "shutdown") {
    std::cout << "the server is shutting down\n";
  }
  const bool noPlan = method == "plan" && !result.at("success").get<bool>();
  return noPlan ? 3 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  PlanOptions plan;
  QualityOptions quality;
  CLI::App app{"hfts-client: talks to hfts-server (docs/protocol.md)"};
  app.require_subcommand(1);
  app.add_option("--host", o.host, "Server address")->capture_default_str();
  app.add_option("--port", o.port, "Server port")->capture_default_str();
  app.add_flag("--json", o.json, "Print the raw JSON result");
  app.add_option("--out", o.out, "Also save the JSON result to FILE")->type_name("FILE");
  app.add_option("--retries", o.retries,
                 "Connect and send again this often when the connection fails before the "
                 "answer (not for shutdown)")
      ->check(CLI::Range(0, 100))
      ->capture_default_str();
  app.add_option("--token-file", o.token_file,
                 "The token for a server with --auth-tokens: the file's first line (default: "
                 "the environment variable HFTS_TOKEN, if set)")
      ->type_name("FILE");
  app.add_flag("--tls", o.tls,
               "Speak TLS; the server's certificate must verify (system CAs, or --ca-file)");
  app.add_option("--ca-file", o.ca_file,
                 "Verify the server's certificate against these CA certificates (PEM; implies "
                 "--tls)")
      ->type_name("FILE");
  app.add_subcommand("info", "Server version, robots, limits and load");
  std::string listedRobot;
  addRobotOption(*app.add_subcommand("objects", "The object databases and their graspability"),
                 listedRobot);
  addRobotOption(*app.add_subcommand("scenes", "The scenes"), listedRobot);
  CLI::App* planCmd = app.add_subcommand("plan", "Plan a grasp and a path to it");
  addPlanOptions(*planCmd, plan);
  CLI::App* qualityCmd = app.add_subcommand("quality", "Ferrari-Canny epsilon of a grasp");
  qualityCmd
      ->add_option("request", quality.file, "Request JSON (docs/grasp_quality.md); - reads stdin")
      ->required();
  qualityCmd->add_option("--object", quality.object,
                         "Contacts are in this object's frame: centre and rho from its database");
  app.add_subcommand("shutdown", "Stop the server (an admin token, when it has tokens)");
  ViewOptions view;
  CLI::App* viewCmd =
      app.add_subcommand("view", "Write a plan as one HTML page with the 3-D viewer (no server)");
  viewCmd->add_option("plan", view.plan, "Plan result JSON (--out of plan ... --gltf)")
      ->required()
      ->check(CLI::ExistingFile);
  viewCmd->add_option("-o,--output", view.output, "The page (default: PLAN with .html)");
  viewCmd->add_option("--glb", view.glb, "The plan's .glb, if the JSON does not hold it")
      ->check(CLI::ExistingFile);
  viewCmd->add_option("--viewer-dir", view.viewer_dir, "The viewer's folder")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  const std::string command = app.get_subcommands().front()->get_name();
  if (command == "view") {
    try {
      return writeView(view);
    } catch (const std::exception& e) {
      std::cerr << "hfts-client: " << e.what() << "\n";
      return 1;
    }
  }
  const std::map<std::string, std::string> methods = {
      {"info", "server.info"}, {"objects", "objects.list"},  {"scenes", "scenes.list"},
      {"plan", "plan"},        {"quality", "grasp.quality"}, {"shutdown", "shutdown"}};
  const std::string& method = methods.at(command);
  try {
    json params = json::object();
    if (command == "plan") {
      if (plan.scene.empty() && plan.scene_file.empty())
        throw std::runtime_error("plan needs --scene NAME or --scene-file FILE");
      params = planParams(plan, *planCmd);
    } else if ((command == "objects" || command == "scenes") && !listedRobot.empty()) {
      params["robot"] = listedRobot;
    } else if (command == "quality") {
      params = readJsonFile(quality.file);
      if (!quality.object.empty() && params.is_object()) params["object"] = quality.object;
    }
    hfts::client::RetryPolicy retry;
    retry.retries = o.retries;
    retry.on_retry = [&](const std::string& why, int attempt) {
      std::cerr << "hfts-client: " << why << "; trying again (attempt " << attempt << " of "
                << o.retries + 1 << ")\n";
    };
    hfts::client::Access access;
    access.token = hfts::client::tokenFrom(o.token_file);
    access.tls = o.tls || !o.ca_file.empty();
    access.ca_file = o.ca_file;
    hfts::client::RpcClient client(o.host, o.port, retry, access);
    const json result = client.call(method, params);
    const int status = output(o, method, result);
    if (command == "plan" && !plan.trajectory_csv.empty() && status == 0) {
      std::ostringstream csv;
      hfts::client::writeTrajectoryCsv(result, csv);
      hfts::core::writeFileAtomically(plan.trajectory_csv, csv.str());
    }
    if (command == "plan" && !plan.ros.empty() && status == 0)
      hfts::core::writeFileAtomically(plan.ros, result.at("ros").dump(2) + "\n");
    if (command == "plan" && !plan.gltf.empty() && status == 0) {
      if (!result.contains("gltf"))
        throw std::runtime_error("the plan has no trajectory to animate");
      hfts::core::writeFileAtomically(
          plan.gltf, hfts::core::base64Decode(result.at("gltf").get<std::string>(), "gltf"));
    }
    return status;
  } catch (const hfts::client::RpcCallError& e) {
    std::cerr << "hfts-client: " << method << " failed: " << e.what() << " (error " << e.code()
              << ")\n";
  } catch (const std::exception& e) {
    std::cerr << "hfts-client: " << e.what() << "\n";
  }
  return 1;
}
