#include "service/plan_request_json.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/base64.h"
#include "robot/sensor_files.h"
#include "service/catalog_json.h"
#include "service/rpc_error.h"
#include "service_catalog.h"

namespace hfts::service {
namespace {

using nlohmann::json;

planner::PlanRequest parse(const json& params, double maxTimeLimit = 60.0) {
  return planRequestFromJson(params, test::serviceCatalog(), PlanLimits{maxTimeLimit});
}

/// Expects an invalid-params error naming `field` whose message contains `words`.
void expectRejected(const json& params, const std::string& field, const std::string& words) {
  try {
    parse(params);
    ADD_FAILURE() << "accepted " << params.dump();
  } catch (const RpcError& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidParams);
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind(field + ": ", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

json start() {
  return {0, -1.5, 1.5, 0, 1.5, 0, 0, -0.2, 0.2, -0.2, 0.2, -0.2, 0.2};
}

TEST(PlanRequestJson, ASceneNameGivesTheSceneAndItsTarget) {
  const planner::PlanRequest r = parse({{"scene", "bin"}});
  EXPECT_EQ(r.scene.name, "bin");
  EXPECT_EQ(r.object, "blob");
  EXPECT_EQ(r.scene.obstacles.size(), 7u);
  EXPECT_FALSE(r.object_pose.has_value());
  EXPECT_FALSE(r.start.has_value());
  EXPECT_EQ(r.algorithm, planner::PlanAlgorithm::kCoupled);
  EXPECT_EQ(r.seed, 1u);
  EXPECT_EQ(r.time_limit, 60.0) << "the default is the server's maximum";
  EXPECT_TRUE(r.parameters.empty());
}

TEST(PlanRequestJson, MapsEveryField) {
  const planner::PlanRequest r =
      parse({{"scene", "table"},
             {"object", "bottle"},
             {"object_pose", {{"position", {0.5, 0.1, 0.0}}, {"orientation", {0, 0, 2, 0}}}},
             {"start", start()},
             {"time_limit", 2.5},
             {"algorithm", "decoupled"},
             {"iterations", 60},
             {"seed", 18446744073709551615u},
             {"trajectory_rate", 250},
             {"explored", true},
             {"parameters", {{"p_max", 0.8}, {"kappa", 3}, {"step_size", "0.2"}}}});
  EXPECT_EQ(r.object, "bottle");
  ASSERT_TRUE(r.object_pose.has_value());
  EXPECT_TRUE(r.object_pose->translation().isApprox(Eigen::Vector3d(0.5, 0.1, 0.0)));
  EXPECT_TRUE(r.object_pose->linear().isApprox(
      Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix()))
      << "quaternions are normalised, ROS order";
  ASSERT_TRUE(r.start.has_value());
  EXPECT_DOUBLE_EQ((*r.start)(1), -1.5);
  EXPECT_EQ(r.time_limit, 2.5);
  EXPECT_EQ(r.algorithm, planner::PlanAlgorithm::kDecoupled);
  EXPECT_EQ(r.iterations, 60);
  EXPECT_EQ(r.seed, 18446744073709551615u);
  EXPECT_EQ(r.trajectory_rate, 250.0);
  EXPECT_TRUE(r.explored);
  EXPECT_EQ(r.parameters, (std::map<std::string, std::string>{
                              {"kappa", "3"}, {"p_max", "0.8"}, {"step_size", "0.2"}}));
}

TEST(PlanRequestJson, AlgorithmPaperIsTheCoupledPlannerWithThePapersSettings) {
  const planner::PlanRequest paper = parse({{"scene", "table"}, {"algorithm", "paper"}});
  EXPECT_EQ(paper.algorithm, planner::PlanAlgorithm::kCoupled);
  EXPECT_EQ(paper.preset, planner::PlannerPreset::kPaper);
  const planner::PlanRequest coupled = parse({{"scene", "table"}, {"algorithm", "coupled"}});
  EXPECT_EQ(coupled.preset, planner::PlannerPreset::kDefault);
  EXPECT_EQ(parse({{"scene", "table"}}).preset, planner::PlannerPreset::kDefault);
}

TEST(PlanRequestJson, LiftIsOnByDefaultButForThePapersPlanner) {
  const planner::PlanRequest plain = parse({{"scene", "table"}});
  ASSERT_TRUE(plain.lift.has_value());
  EXPECT_EQ(plain.lift->height, planner::LiftOptions{}.height);
  EXPECT_FALSE(parse({{"scene", "table"}, {"algorithm", "paper"}}).lift.has_value());
  EXPECT_FALSE(parse({{"scene", "table"}, {"lift", false}}).lift.has_value());
  const planner::PlanRequest high =
      parse({{"scene", "table"}, {"algorithm", "paper"}, {"lift", {{"height", 0.2}}}});
  ASSERT_TRUE(high.lift.has_value());
  EXPECT_EQ(high.lift->height, 0.2);
  EXPECT_TRUE(parse({{"scene", "table"}, {"lift", true}}).lift.has_value());
  expectRejected({{"scene", "table"}, {"lift", {{"height", 2.0}}}}, "lift.height", "(0, 1]");
  expectRejected({{"scene", "table"}, {"lift", {{"height", -0.1}}}}, "lift.height", "> 0");
  expectRejected({{"scene", "table"}, {"lift", {{"high", 0.1}}}}, "lift.high", "");
  const planner::PlanRequest slow = parse({{"scene", "table"}, {"lift", {{"held_speed", 0.25}}}});
  ASSERT_TRUE(slow.lift.has_value());
  EXPECT_EQ(slow.lift->held_speed, 0.25);
  EXPECT_EQ(slow.lift->height, planner::LiftOptions{}.height);
  EXPECT_EQ(plain.lift->held_speed, planner::LiftOptions{}.held_speed);
  expectRejected({{"scene", "table"}, {"lift", {{"held_speed", 1.5}}}}, "lift.held_speed",
                 "(0, 1]");
  expectRejected({{"scene", "table"}, {"lift", {{"held_speed", 0.0}}}}, "lift.held_speed", "> 0");
  expectRejected({{"scene", "table"}, {"lift", 0.1}}, "lift", "true, false or");
  expectRejected({{"scene", "table"}, {"goal", {{"joints", start()}}}, {"lift", true}}, "lift",
                 "no object to lift");
}

TEST(PlanRequestJson, APlaceGoalIsARegionOfTheScenesSupports) {
  const planner::PlanRequest plain = parse({{"scene", "table"}});
  EXPECT_FALSE(plain.place.has_value());
  const planner::PlanRequest place =
      parse({{"scene", "table"},
             {"place",
              {{"on", "table"},
               {"area", {{"min", {0.3, -0.4}}, {"max", {0.4, -0.3}}}},
               {"upright", true},
               {"search", "decoupled"}}}});
  ASSERT_TRUE(place.place.has_value());
  EXPECT_EQ(place.place->on, "table");
  ASSERT_TRUE(place.place->area.has_value());
  EXPECT_EQ(place.place->area->min(), Eigen::Vector2d(0.3, -0.4));
  EXPECT_EQ(place.place->area->max(), Eigen::Vector2d(0.4, -0.3));
  EXPECT_TRUE(place.place->upright);
  EXPECT_EQ(place.place_search, planner::PlaceSearch::kDecoupled);
  EXPECT_EQ(parse({{"scene", "table"}, {"place", {{"on", "table"}}}}).place_search,
            planner::PlaceSearch::kCoupled);
  expectRejected({{"scene", "table"}, {"place", {{"on", "shelf_board"}}}}, "place.on",
                 "no obstacle 'shelf_board'");
  expectRejected({{"scene", "table"}, {"place", {{"on", "can_left"}}}}, "place.on", "not a box");
  expectRejected({{"scene", "table"},
                  {"place", {{"on", "table"}, {"area", {{"min", {3, 3}}, {"max", {4, 4}}}}}}},
                 "place.area", "off the top");
  expectRejected({{"scene", "table"}, {"place", {{"on", "table"}, {"search", "random"}}}},
                 "place.search", "coupled");
  expectRejected({{"scene", "table"}, {"place", {{"on", "table"}, {"height", 1}}}}, "place.height",
                 "");
  expectRejected({{"scene", "table"}, {"place", "table"}}, "place", "must be an object");
  expectRejected({{"scene", "table"}, {"lift", false}, {"place", {{"on", "table"}}}}, "place",
                 "lift");
  expectRejected(
      {{"scene", "table"}, {"goal", {{"joints", start()}}}, {"place", {{"on", "table"}}}}, "place",
      "no object to place");
}

TEST(PlanRequestJson, CapsTheTimeLimit) {
  EXPECT_EQ(parse({{"scene", "bin"}, {"time_limit", 100}}, 10.0).time_limit, 10.0);
  EXPECT_EQ(parse({{"scene", "bin"}}, 10.0).time_limit, 10.0);
}

TEST(PlanRequestJson, AcceptsAnInlineSceneOfPrimitives) {
  const json scene = {
      {"name", "mine"},
      {"robot_base", {{"position", {0, 0, 0}}, {"orientation", {0, 0, 0, 1}}}},
      {"obstacles",
       {{{"name", "floor"},
         {"type", "box"},
         {"size", {2, 2, 0.02}},
         {"pose", {{"position", {0.5, 0, -0.011}}, {"orientation", {0, 0, 0, 1}}}}}}},
      {"target",
       {{"object", "mug"}, {"pose", {{"position", {0.6, 0, 0}}, {"orientation", {0, 0, 0, 1}}}}}}};
  const planner::PlanRequest r = parse({{"scene", scene}});
  EXPECT_EQ(r.scene.name, "mine");
  EXPECT_EQ(r.object, "mug");
  ASSERT_EQ(r.scene.obstacles.size(), 1u);
  EXPECT_EQ(r.scene.obstacles[0].name, "floor");
  json withMesh = scene;
  withMesh["obstacles"].push_back({{"name", "m"},
                                   {"type", "mesh"},
                                   {"mesh", "../meshes/mug.ply"},
                                   {"pose", scene["robot_base"]}});
  expectRejected({{"scene", withMesh}}, "scene.obstacles[1]", "may not load mesh files");
  json withCloudFile = scene;
  withCloudFile["obstacles"].push_back({{"name", "c"},
                                        {"type", "points"},
                                        {"file", "/etc/hostname.pcd"},
                                        {"pose", scene["robot_base"]}});
  expectRejected({{"scene", withCloudFile}}, "scene.obstacles[1].file", "may not load files");
  json withPoints = scene;
  withPoints["obstacles"].push_back({{"name", "c"},
                                     {"type", "points"},
                                     {"points", {{0.3, 0.3, 0.5}, {0.31, 0.3, 0.5}}},
                                     {"pose", scene["robot_base"]}});
  const planner::PlanRequest clouded = parse({{"scene", withPoints}});
  ASSERT_EQ(clouded.scene.obstacles.size(), 2u);
  EXPECT_EQ(clouded.scene.obstacles[1].type, robot::Obstacle::Type::kPoints);
  EXPECT_GE(clouded.scene.obstacles[1].cloud->occupied_count, 2u);
  json broken = scene;
  broken["obstacles"][0]["size"] = {2, 2, -1};
  expectRejected({{"scene", broken}}, "scene.obstacles[0].size", "must be positive");
}

/// A depth_image obstacle: a camera 1.2 m above the table's middle looking
/// down, seeing the table top everywhere (a 4 x 4 image, inline).
json cameraAbove(const std::string& name) {
  const robot::DepthImage image{4, 4, std::vector<float>(16, 1.2f)};
  return {{"name", name},
          {"type", "depth_image"},
          {"png_base64", core::base64Encode(robot::encodeDepthPng(image))},
          {"units", "mm"},
          {"intrinsics", {{"fx", 4}, {"fy", 4}, {"cx", 1.5}, {"cy", 1.5}}},
          {"pose", {{"position", {0.55, 0, 1.2}}, {"orientation", {1, 0, 0, 0}}}}};
}

TEST(PlanRequestJson, ObstaclesAreAppendedToTheScene) {
  const json seen = {{"name", "seen"},
                     {"type", "points"},
                     {"points", {{0.3, 0.3, 0.5}, {0.31, 0.3, 0.5}}},
                     {"pose", {{"position", {0, 0, 0}}, {"orientation", {0, 0, 0, 1}}}}};
  const planner::PlanRequest r =
      parse({{"scene", "table"}, {"obstacles", {cameraAbove("camera"), seen}}});
  ASSERT_EQ(r.scene.obstacles.size(), 9u);  // the table scene's 7, then these
  EXPECT_EQ(r.scene.obstacles[0].name, "table");
  EXPECT_EQ(r.scene.obstacles[7].name, "camera");
  EXPECT_EQ(r.scene.obstacles[7].type, robot::Obstacle::Type::kPoints);
  EXPECT_NEAR(robot::topOf(r.scene.obstacles[7]), 0.0, 0.02) << "the table top, seen";
  EXPECT_EQ(r.scene.obstacles[8].name, "seen");
  EXPECT_EQ(r.object, "mug");
  EXPECT_EQ(parse({{"scene", "table"}, {"obstacles", json::array()}}).scene.obstacles.size(), 7u);
  // An inline scene takes them too.
  const json inlineScene = {
      {"name", "mine"},
      {"robot_base", {{"position", {0, 0, 0}}, {"orientation", {0, 0, 0, 1}}}},
      {"obstacles", json::array()},
      {"target",
       {{"object", "mug"}, {"pose", {{"position", {0.6, 0, 0}}, {"orientation", {0, 0, 0, 1}}}}}}};
  const planner::PlanRequest mine = parse({{"scene", inlineScene}, {"obstacles", {seen}}});
  ASSERT_EQ(mine.scene.obstacles.size(), 1u);
  EXPECT_EQ(mine.scene.obstacles[0].name, "seen");
}

TEST(PlanRequestJson, ObstaclesMayNotNameFilesNorClashWithTheScenes) {
  expectRejected({{"scene", "table"}, {"obstacles", cameraAbove("camera")}}, "obstacles",
                 "must be an array");
  json file = cameraAbove("camera");
  file.erase("png_base64");
  file["file"] = "/etc/hostname.png";
  expectRejected({{"scene", "table"}, {"obstacles", {file}}}, "obstacles[0].file",
                 "may not load files");
  json mask = cameraAbove("camera");
  mask["mask"] = "mask.png";
  expectRejected({{"scene", "table"}, {"obstacles", {mask}}}, "obstacles[0].mask",
                 "may not load files");
  const json mesh = {{"name", "m"},
                     {"type", "mesh"},
                     {"mesh", "../meshes/mug.ply"},
                     {"pose", {{"position", {0, 0, 0}}, {"orientation", {0, 0, 0, 1}}}}};
  expectRejected({{"scene", "table"}, {"obstacles", {mesh}}}, "obstacles[0]",
                 "may not load mesh files");
  expectRejected({{"scene", "table"}, {"obstacles", {cameraAbove("camera"), cameraAbove("jar")}}},
                 "obstacles[1].name", "'jar' is an obstacle of scene 'table' already");
  expectRejected(
      {{"scene", "table"}, {"obstacles", {cameraAbove("camera"), cameraAbove("camera")}}},
      "obstacles[1].name", "used by another obstacle");
  json blind = cameraAbove("camera");
  blind["intrinsics"]["fx"] = 0;
  expectRejected({{"scene", "table"}, {"obstacles", {blind}}}, "obstacles[0].intrinsics.fx",
                 "must be a positive number");
  json notNpy = cameraAbove("camera");
  notNpy.erase("png_base64");
  notNpy["npy_base64"] = "AAAA";
  expectRejected({{"scene", "table"}, {"obstacles", {notNpy}}}, "obstacles[0].npy_base64",
                 "not a NumPy .npy file");
}

TEST(PlanRequestJson, TheRobotFieldPicksWhoseJointsAndParametersCount) {
  const PlanningCatalog& two = test::twoRobotCatalog();
  const auto parseFor = [&](const json& params) {
    return planRequestFromJson(params, two, PlanLimits{60.0});
  };
  const json panda = {{"scene", "table"}, {"robot", "panda_gripper"}};
  EXPECT_EQ(&requestedRobot(panda, two), two.findRobot("panda_gripper"));
  EXPECT_EQ(&requestedRobot({{"scene", "table"}}, two), &two.robots().front());
  json eight = panda;  // seven arm joints and the jaws
  eight["start"] = {0, -0.3, 0, -2.2, 0, 2.0, 0.8, 0.04};
  ASSERT_TRUE(parseFor(eight).start.has_value());
  EXPECT_EQ(parseFor(eight).start->size(), 8);
  eight["parameters"] = {{"unstable_by_reach", 0}};  // declared for every robot
  EXPECT_EQ(parseFor(eight).parameters.at("unstable_by_reach"), "0");
  // The KR5's 13 values are wrong for the Panda, and the other way round.
  json thirteen = panda;
  thirteen["start"] = start();
  try {
    parseFor(thirteen);
    ADD_FAILURE() << "a 13-value start accepted for the Panda";
  } catch (const RpcError& e) {
    EXPECT_EQ(e.field(), "start");
    EXPECT_NE(std::string(e.what()).find(
                  "must hold 8 values, one per joint of robot 'panda_gripper', got 13"),
              std::string::npos);
  }
  eight.erase("robot");
  EXPECT_THROW(parseFor(eight), RpcError) << "the default robot has 13 joints";
  try {
    parseFor({{"scene", "table"}, {"robot", "ur5e"}});
    ADD_FAILURE() << "an unknown robot accepted";
  } catch (const RpcError& e) {
    EXPECT_EQ(e.field(), "robot");
    EXPECT_NE(std::string(e.what()).find("(this server plans for: kr5_sdh, panda_gripper)"),
              std::string::npos)
        << e.what();
  }
}

TEST(PlanRequestJson, RejectsUnknownAndUnsafeNames) {
  expectRejected(json::object(), "scene", "required");
  expectRejected({{"scene", "kitchen"}}, "scene",
                 "unknown scene 'kitchen' (known: bin, shelf, table)");
  expectRejected({{"scene", "../scenes/table"}}, "scene", "path characters");
  expectRejected({{"scene", "bin"}, {"object", "teapot"}}, "object", "unknown object 'teapot'");
  expectRejected({{"scene", "bin"}, {"object", "/tmp/mug"}}, "object", "path characters");
  expectRejected({{"scene", "bin"}, {"object", ".hidden"}}, "object", "not a valid name");
  expectRejected({{"scene", "bin"}, {"robot", "x"}}, "robot",
                 "unknown robot 'x' (this server plans for: kr5_sdh)");
  expectRejected({{"scene", "bin"}, {"robot", "../kr5_sdh"}}, "robot", "path characters");
  expectRejected({{"scene", "bin"}, {"robot", 5}}, "robot", "string");
  expectRejected({{"scene", "bin"}, {"rob", "kr5_sdh"}}, "rob", "unknown field");
  expectRejected({{"scene", "bin"}, {"parameters", {{"warp", 1}}}}, "parameters.warp",
                 "unknown planner parameter");
  expectRejected({{"scene", "bin"}, {"parameters", {{"time_limit", 1}}}}, "parameters.time_limit",
                 "top-level 'time_limit'");
}

TEST(PlanRequestJson, RejectsBadNumbersAndShapes) {
  json shortStart = start();
  shortStart.erase(12);
  expectRejected({{"scene", "bin"}, {"start", shortStart}}, "start",
                 "must hold 13 values, one per joint of robot 'kr5_sdh', got 12");
  json textStart = start();
  textStart[4] = "x";
  expectRejected({{"scene", "bin"}, {"start", textStart}}, "start[4]", "must be a number");
  json farStart = start();
  farStart[0] = 10.0;
  expectRejected({{"scene", "bin"}, {"start", farStart}}, "start", "outside the joint limits");
  expectRejected(
      {{"scene", "bin"}, {"object_pose", {{"position", {0, 0, 0}}, {"orientation", {0, 0, 0, 0}}}}},
      "object_pose.orientation", "zero norm");
  expectRejected({{"scene", "bin"}, {"object_pose", {{"position", {0, 0, 0}}}}},
                 "object_pose.orientation", "required");
  expectRejected({{"scene", "bin"}, {"time_limit", 0}}, "time_limit", "> 0");
  expectRejected({{"scene", "bin"}, {"time_limit", "1"}}, "time_limit", "must be a number");
  expectRejected({{"scene", "bin"}, {"seed", 1.5}}, "seed", "integer >= 0");
  expectRejected({{"scene", "bin"}, {"seed", -2}}, "seed", "integer >= 0");
  expectRejected({{"scene", "bin"}, {"algorithm", "decoupled"}, {"iterations", 0}}, "iterations",
                 ">= 1");
  expectRejected({{"scene", "bin"}, {"iterations", 20}}, "iterations", "only the decoupled");
  expectRejected({{"scene", "bin"}, {"algorithm", 2}}, "algorithm", "string");
  expectRejected({{"scene", "bin"}, {"trajectory_rate", -1}}, "trajectory_rate", "[0, 1000]");
  expectRejected({{"scene", "bin"}, {"explored", 1}}, "explored", "true or false");
  expectRejected({{"scene", "bin"}, {"trajectory_rate", 1e4}}, "trajectory_rate", "[0, 1000]");
  expectRejected({{"scene", "bin"}, {"trajectory_rate", "100"}}, "trajectory_rate", "number");
  expectRejected({{"scene", "bin"}, {"parameters", {{"p_max", true}}}}, "parameters.p_max",
                 "number or a string");
  expectRejected(json::array(), "params", "must be an object");
}

TEST(PlanRequestJson, GoalsMakeAMotionPlan) {
  const json arm = {0.3, -1.2, 1.4, 0, 1.2, 0};
  const json pose = {{"position", {0.6, 0.1, 0.5}}, {"orientation", {0, 1, 0, 0}}};
  const planner::PlanRequest r = parse({{"scene", "bin"},
                                        {"start", start()},
                                        {"goals",
                                         {{{"joints", arm}},
                                          {{"pose", pose},
                                           {"link", "palm"},
                                           {"position_tolerance", 0.002},
                                           {"orientation_tolerance", 0.05}}}}});
  ASSERT_EQ(r.goals.size(), 2u);
  const auto& joint = std::get<planner::JointGoal>(r.goals[0]);
  EXPECT_EQ(joint.configuration.size(), 6) << "the arm's only; the planner adds the hand";
  EXPECT_DOUBLE_EQ(joint.configuration(2), 1.4);
  const auto& goal = std::get<planner::PoseGoal>(r.goals[1]);
  EXPECT_EQ(goal.link, "palm");
  EXPECT_TRUE(goal.pose.translation().isApprox(Eigen::Vector3d(0.6, 0.1, 0.5)));
  EXPECT_NEAR(goal.pose.linear()(0, 0), -1.0, 1e-12);
  EXPECT_DOUBLE_EQ(goal.position_tolerance, 0.002);
  EXPECT_DOUBLE_EQ(goal.orientation_tolerance, 0.05);
  EXPECT_EQ(r.object, "blob") << "the scene's target stays, as an obstacle";

  const planner::PlanRequest one = parse({{"scene", "bin"}, {"goal", {{"pose", pose}}}});
  ASSERT_EQ(one.goals.size(), 1u);
  EXPECT_DOUBLE_EQ(std::get<planner::PoseGoal>(one.goals[0]).position_tolerance, 0.001);
}

TEST(PlanRequestJson, RejectsMalformedGoals) {
  const json pose = {{"position", {0.6, 0.1, 0.5}}, {"orientation", {0, 1, 0, 0}}};
  const json arm = {0.3, -1.2, 1.4, 0, 1.2, 0};
  expectRejected({{"scene", "bin"}, {"goal", {{"joints", {0.1, 0.2}}}}}, "goal.joints",
                 "needs 13 values (every DoF) or 6 (the arm's), got 2");
  expectRejected(
      {{"scene", "bin"}, {"goals", {{{"joints", arm}}, {{"joints", {9, 0, 0, 0, 0, 0}}}}}},
      "goals[1].joints", "a1");
  expectRejected({{"scene", "bin"}, {"goal", {{"joints", {0.3, "x", 1.4, 0, 1.2, 0}}}}},
                 "goal.joints[1]", "must be a number");
  expectRejected({{"scene", "bin"}, {"goal", {{"pose", pose}, {"link", "finger_1_distal"}}}},
                 "goal.link", "must be the flange link");
  expectRejected({{"scene", "bin"}, {"goal", {{"pose", pose}, {"position_tolerance", -0.1}}}},
                 "goal.position_tolerance", "[0, 0.5");
  expectRejected({{"scene", "bin"}, {"goal", {{"pose", pose}, {"orientation_tolerance", 4}}}},
                 "goal.orientation_tolerance", "[0, pi]");
  expectRejected({{"scene", "bin"}, {"goal", {{"joints", arm}, {"pose", pose}}}}, "goal.pose",
                 "either");
  expectRejected({{"scene", "bin"}, {"goal", json::object()}}, "goal.joints", "either");
  expectRejected({{"scene", "bin"}, {"goal", {{"joints", arm}, {"link", "x"}}}}, "goal.joints",
                 "no link");
  expectRejected({{"scene", "bin"}, {"goal", {{"joints", arm}}}, {"goals", json::array()}}, "goals",
                 "either");
  expectRejected({{"scene", "bin"}, {"goals", json::array()}}, "goals", "1 to 1000 goals");
  expectRejected({{"scene", "bin"}, {"goal", 3}}, "goal", "must be an object");
  expectRejected({{"scene", "bin"}, {"goal", {{"joints", arm}}}, {"validate", true}}, "validate",
                 "no grasp");
}

TEST(PlanRequestJson, RacingCopiesAreCappedAtTheServersWorkers) {
  const json two = {{"scene", "bin"}, {"parameters", {{"threads", 2}}}};
  expectRejected(two, "parameters.threads", "at most 1 on this server (its planning workers)");
  // As text too: planGrasp would read "32" as 32 copies.
  expectRejected({{"scene", "bin"}, {"parameters", {{"threads", "32"}}}}, "parameters.threads",
                 "at most 1 on this server (its planning workers), got 32");
  const planner::PlanRequest r =
      planRequestFromJson(two, test::serviceCatalog(), PlanLimits{60.0, 2});
  EXPECT_EQ(r.parameters.at("threads"), "2");
  // Every value meets the planner's own check when the request is read.
  expectRejected({{"scene", "bin"}, {"parameters", {{"threads", "many"}}}}, "parameters.threads",
                 "must be an integer, got 'many'");
  expectRejected({{"scene", "bin"}, {"parameters", {{"p_max", 5}}}}, "parameters.p_max",
                 "must be in [0, 1], got 5");
}

TEST(PlanRequestJson, NonFiniteNumbersAreRejected) {
  // JSON text cannot carry NaN; a json value built in C++ can.
  json pose = {{"position", {0, std::nan(""), 0}}, {"orientation", {0, 0, 0, 1}}};
  expectRejected({{"scene", "bin"}, {"object_pose", pose}}, "object_pose.position[1]", "finite");
  expectRejected({{"scene", "bin"}, {"time_limit", INFINITY}}, "time_limit", "finite");
  expectRejected({{"scene", "bin"}, {"parameters", {{"p_max", NAN}}}}, "parameters.p_max",
                 "finite");
}

}  // namespace
}  // namespace hfts::service
