#include "service/plan_result_json.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "robot_fixture.h"

namespace hfts::service {
namespace {

using nlohmann::json;

planner::PlanRequest request() {
  planner::PlanRequest r;
  r.scene = robot::loadScene(test::sourcePath("objects/scenes/table.json"));
  r.scene.name = "table";
  r.object = "mug";
  r.seed = 7;
  r.time_limit = 5.0;
  return r;
}

planner::PlanResult success() {
  const robot::RobotModel& robot = test::kr5Sdh();
  planner::PlanResult r;
  r.success = true;
  r.joint_names = robot.dofNames();
  r.path = {robot.home(), robot.home() * 0.5, robot.home() * 0.25};
  planner::PlannedGrasp& g = r.grasp;
  g.node.level = 3;
  g.node.parts = {4, 5, 6, 0};
  g.contacts_object = Eigen::Matrix3Xd::Identity(3, 3);
  g.contacts_world = 2.0 * g.contacts_object;
  g.inward_normals_object = -g.contacts_object;
  g.inward_normals_world = -g.contacts_object;
  g.epsilon = 0.125;
  g.reachability = 0.001;
  g.fingertip_error = 0.002;
  g.planned_epsilon = 0.04;
  g.penetration = 0.0003;
  g.planned_contacts_object = 3.0 * g.contacts_object;
  g.hand_configuration = robot.home().tail(robot.numHandDofs());
  r.stats.planning_time = 0.5;
  r.stats.iterations = 42;
  r.stats.path_length_smoothed = 1.5;
  r.stats.certificate_queries = 1234;
  r.clearance = 0.0125;
  return r;
}

TEST(PlanResultJson, CarriesThePathWithItsJointNames) {
  const json j = planResultToJson(success(), request());
  EXPECT_EQ(j.at("success"), true);
  EXPECT_EQ(j.at("reason"), "none");
  EXPECT_EQ(j.at("message"), "");
  EXPECT_EQ(j.at("joint_names"), test::kr5Sdh().dofNames());
  ASSERT_EQ(j.at("path").size(), 3u);
  EXPECT_EQ(j.at("clearance"), 0.0125);
  EXPECT_EQ(j.at("path")[1].size(), 13u);
  EXPECT_DOUBLE_EQ(j.at("path")[1][1].get<double>(), test::kr5Sdh().home()(1) * 0.5);
}

TEST(PlanResultJson, DescribesTheGrasp) {
  const json g = planResultToJson(success(), request()).at("grasp");
  EXPECT_EQ(g.at("node"), json::parse(R"({"level": 3, "partitions": [4, 5, 6]})"));
  ASSERT_EQ(g.at("contacts_world").size(), 3u);
  EXPECT_EQ(g.at("contacts_world")[1],
            json::parse(R"({"position": [0, 2, 0], "normal": [0, -1, 0]})"));
  EXPECT_EQ(g.at("contacts_object")[2].at("position"), json({0, 0, 1}));
  EXPECT_EQ(g.at("normals"), "inward");
  EXPECT_EQ(g.at("epsilon"), 0.125);
  EXPECT_EQ(g.at("reachability"), 0.001);
  EXPECT_EQ(g.at("fingertip_error"), 0.002);
  EXPECT_EQ(g.at("planned_epsilon"), 0.04);
  EXPECT_EQ(g.at("penetration"), 0.0003);
  EXPECT_EQ(g.at("planned_contacts_object")[1], json({0, 3, 0}));
  EXPECT_EQ(g.at("hand_joint_names").size(), 7u);
  EXPECT_EQ(g.at("hand_joint_names")[0], test::kr5Sdh().dofNames()[6]);
  EXPECT_EQ(g.at("hand_configuration").size(), 7u);
}

TEST(PlanResultJson, CarriesTheLift) {
  planner::PlanResult result = success();
  EXPECT_TRUE(planResultToJson(result, request()).at("lift").is_null());
  result.lift = planner::LiftPath{{test::kr5Sdh().home(), test::kr5Sdh().home() * 0.5}, "retreat"};
  const json lift = planResultToJson(result, request()).at("lift");
  EXPECT_EQ(lift.at("direction"), "retreat");
  ASSERT_EQ(lift.at("path").size(), 2u);
  EXPECT_DOUBLE_EQ(lift.at("path")[1][1].get<double>(), test::kr5Sdh().home()(1) * 0.5);
}

TEST(PlanResultJson, CarriesThePlacementOfAPickAndPlace) {
  planner::PlanResult result = success();
  EXPECT_FALSE(planResultToJson(result, request()).contains("place"));
  planner::PlanRequest r = request();
  r.place = planner::PlaceGoal{"table", std::nullopt, false};
  EXPECT_TRUE(planResultToJson(result, r).at("place").is_null());
  result.place_rejected.descent_blocked = 3;
  planner::Placement p;
  p.object_pose = Eigen::Isometry3d(Eigen::Translation3d(0.4, -0.3, 0.001));
  p.tipping_angle = 0.5;
  const Eigen::VectorXd home = test::kr5Sdh().home();
  p.carry = {home, home * 0.5};
  p.descent = {home * 0.5, home * 0.25};
  p.open = home * 0.25;
  p.retreat = {home * 0.25, home * 0.125};
  p.retreat_direction = "back";
  p.rest.stable = true;
  p.rest.displacement = 0.0005;
  result.place = p;
  result.trajectory.points.push_back({0.0, home, home, home});
  result.trajectory.release_start = 2.5;
  const json j = planResultToJson(result, r);
  const json& place = j.at("place");
  EXPECT_EQ(place.at("object_pose").at("position"), json({0.4, -0.3, 0.001}));
  EXPECT_EQ(place.at("tipping_angle"), 0.5);
  EXPECT_EQ(place.at("carry").size(), 2u);
  EXPECT_DOUBLE_EQ(place.at("descent")[1][1].get<double>(), home(1) * 0.25);
  EXPECT_EQ(place.at("open").size(), 13u);
  EXPECT_EQ(place.at("retreat_direction"), "back");
  EXPECT_EQ(place.at("rest").at("stable"), true);
  EXPECT_EQ(place.at("rest").at("displacement"), 0.0005);
  EXPECT_EQ(j.at("place_rejected").at("descent_blocked"), 3);
  EXPECT_EQ(j.at("place_rejected").size(), 7u);
  EXPECT_EQ(j.at("trajectory").at("release_start"), 2.5);
}

TEST(PlanResultJson, EchoesTheRequestAndStatistics) {
  planner::PlanRequest r = request();
  r.algorithm = planner::PlanAlgorithm::kDecoupled;
  r.object_pose = Eigen::Isometry3d(Eigen::Translation3d(0.1, 0.2, 0.3));
  planner::PlanResult result = success();
  result.object_pose = *r.object_pose;  // where planGrasp put the object
  result.seed = 99;                     // a racing copy's seed won
  const json j = planResultToJson(result, r);
  EXPECT_EQ(j.at("scene"), "table");
  EXPECT_EQ(j.at("object"), "mug");
  EXPECT_EQ(j.at("algorithm"), "decoupled");
  EXPECT_EQ(j.at("seed"), 7);
  EXPECT_EQ(j.at("plan_seed"), 99);
  EXPECT_EQ(j.at("time_limit"), 5.0);
  EXPECT_EQ(j.at("object_pose"),
            json::parse(R"({"position": [0.1, 0.2, 0.3], "orientation": [0, 0, 0, 1]})"));
  EXPECT_EQ(j.at("stats").at("planning_time"), 0.5);
  EXPECT_EQ(j.at("stats").at("iterations"), 42);
  EXPECT_EQ(j.at("stats").at("path_length_smoothed"), 1.5);
  EXPECT_EQ(j.at("stats").size(), 30u);
  EXPECT_EQ(j.at("stats").at("smoothing_time"), 0.0);
  EXPECT_FALSE(j.contains("reached_goal")) << "a grasp plan has no motion goal";
  EXPECT_EQ(j.at("stats").at("certificate_queries"), 1234);
  EXPECT_EQ(j.at("clearance"), 0.0125);
  EXPECT_EQ(j.at("stats").at("rejected_colliding"), 0);
  for (const char* key : {"dropped_goals", "physics_checks", "physics_time",
                          "rejected_no_pad_contact", "rejected_weak_at_contacts"})
    EXPECT_EQ(j.at("stats").at(key), 0) << key;
}

TEST(PlanResultJson, AMotionPlanNamesTheGoalItReachedAndHasNoGrasp) {
  planner::PlanRequest r = request();
  r.goals = {planner::JointGoal{Eigen::VectorXd::Zero(6)},
             planner::JointGoal{Eigen::VectorXd::Ones(6)}};
  planner::PlanResult result = success();
  result.reached_goal = 1;
  const json j = planResultToJson(result, r);
  EXPECT_EQ(j.at("reached_goal"), 1);
  EXPECT_TRUE(j.at("grasp").is_null());
  EXPECT_EQ(j.at("path").size(), result.path.size());
  result.success = false;
  result.reached_goal.reset();
  EXPECT_TRUE(planResultToJson(result, r).at("reached_goal").is_null());
}

TEST(PlanResultJson, TheTrajectoryIsShapedLikeARosJointTrajectory) {
  planner::PlanResult r = success();
  const robot::RobotModel& robot = test::kr5Sdh();
  const planner::TimeOptimalTrajectory t({r.path[0], r.path[1]}, robot.maxVelocities(),
                                         robot.maxAccelerations());
  r.trajectory.points = t.sample(50);
  r.trajectory.duration = r.trajectory.closing_start = t.duration();
  const json j = planResultToJson(r, request()).at("trajectory");
  EXPECT_EQ(j.at("joint_names"), robot.dofNames());
  ASSERT_EQ(j.at("points").size(), r.trajectory.points.size());
  const json& last = j.at("points").back();
  EXPECT_DOUBLE_EQ(last.at("time_from_start").get<double>(), t.duration());
  for (const char* field : {"positions", "velocities", "accelerations"})
    EXPECT_EQ(last.at(field).size(), 13u) << field;
  EXPECT_DOUBLE_EQ(last.at("positions")[1].get<double>(), r.path[1][1]);
  EXPECT_DOUBLE_EQ(j.at("duration").get<double>(), t.duration());
  EXPECT_TRUE(planResultToJson(success(), request()).at("trajectory").is_null());
}

TEST(PlanResultJson, AFailureHasAReasonAndNoGrasp) {
  planner::PlanResult failed;
  failed.failure = planner::PlanFailure::kStartInCollision;
  failed.message = "the start configuration is in collision";
  failed.joint_names = test::kr5Sdh().dofNames();
  failed.object_pose = request().scene.target_pose;
  const json j = planResultToJson(failed, request());
  EXPECT_EQ(j.at("success"), false);
  EXPECT_EQ(j.at("reason"), "start_in_collision");
  EXPECT_EQ(j.at("message"), "the start configuration is in collision");
  EXPECT_TRUE(j.at("grasp").is_null());
  EXPECT_EQ(j.at("path"), json::array());
  EXPECT_TRUE(j.at("clearance").is_null());
  EXPECT_EQ(j.at("object_pose").at("position"), json({0.55, 0, 0})) << "the scene's pose";
}

}  // namespace
}  // namespace hfts::service
