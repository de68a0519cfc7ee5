#include "service/catalog_json.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "grasp/grasp_quality.h"
#include "service/rpc_error.h"
#include "service_catalog.h"

namespace hfts::service {
namespace {

using nlohmann::json;

const json kContacts = json::parse(R"([
  {"position": [1, 0, 0], "normal": [-1, 0, 0]},
  {"position": [-0.5, 0.8660254037844386, 0], "normal": [0.5, -0.8660254037844386, 0]},
  {"position": [-0.5, -0.8660254037844386, 0], "normal": [0.5, 0.8660254037844386, 0]}])");

TEST(CatalogJson, RobotNamesItsJointsAndLimits) {
  const json r = robotJson(test::kr5Sdh());
  EXPECT_EQ(r.at("name"), "kr5_sdh");
  EXPECT_EQ(r.at("joint_names"), test::kr5Sdh().dofNames());
  EXPECT_EQ(r.at("arm_joint_names").size(), 6u);
  EXPECT_EQ(r.at("hand_joint_names").size(), 7u);
  EXPECT_EQ(r.at("lower_limits")[0], test::kr5Sdh().lowerLimits()(0));
  EXPECT_EQ(r.at("upper_limits")[12], test::kr5Sdh().upperLimits()(12));
  EXPECT_EQ(r.at("home").size(), 13u);
  EXPECT_EQ(r.at("fingertips").size(), 3u);
}

TEST(CatalogJson, ListsTheObjectsWithTheirHierarchy) {
  const json o = objectsJson(test::serviceCatalog(), test::serviceCatalog().robots().front());
  EXPECT_EQ(o.at("robot"), "kr5_sdh");
  ASSERT_EQ(o.at("objects").size(), 3u);
  const json& mug = o.at("objects")[2];
  EXPECT_EQ(mug.at("name"), "mug");
  const db::ObjectDatabase& db = *test::serviceCatalog().world().object("mug");
  EXPECT_EQ(mug.at("contacts"), db.numContacts());
  EXPECT_EQ(mug.at("nodes_per_level"), json({20, 80, 320}));
  EXPECT_EQ(mug.at("rho"), db.geometry.rho);
  EXPECT_EQ(mug.at("source_mesh"), "mug.ply");
  EXPECT_EQ(o.at("skipped"), json::array());
  // Graspability in free space: some, not all, sampled leaf grasps.
  const json& g = mug.at("graspability");
  EXPECT_EQ(g.at("sampled"), 1000);
  EXPECT_GT(g.at("reachable").get<int>(), 0);
  EXPECT_LE(g.at("reachable").get<int>(), g.at("stable").get<int>());
  EXPECT_LT(g.at("stable").get<int>(), 1000);
  EXPECT_DOUBLE_EQ(g.at("fraction").get<double>(), g.at("reachable").get<double>() / 1000.0);
}

TEST(CatalogJson, ListsTheScenes) {
  const json s =
      scenesJson(test::serviceCatalog(), test::serviceCatalog().robots().front()).at("scenes");
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[1].at("name"), "shelf");
  EXPECT_EQ(s[1].at("target_object"), "bottle");
  EXPECT_EQ(s[1].at("target_pose"),
            json::parse(R"({"position": [0.62, 0, 0.1], "orientation": [0, 0, 0, 1]})"));
  EXPECT_EQ(s[1].at("start").size(), 13u);
  EXPECT_TRUE(s[0].at("start").is_null()) << "the bin scene starts at home";
  EXPECT_EQ(s[0].at("obstacles")[6], json::parse(R"({"name": "can_in_bin", "type": "cylinder"})"));
}

TEST(CatalogJson, EveryRobotIsListedAndTheListingsAreItsOwn) {
  const PlanningCatalog& two = test::twoRobotCatalog();
  const json robots = robotsJson(two);
  ASSERT_EQ(robots.size(), 2u);
  EXPECT_EQ(robots[0].at("name"), "kr5_sdh");
  EXPECT_EQ(robots[1].at("name"), "panda_gripper");
  EXPECT_EQ(robots[1].at("joint_names").size(), 8u);
  EXPECT_EQ(robots[1].at("fingertips").size(), 2u);
  EXPECT_EQ(robots[1].at("planner_parameters").size(), two.robots()[1].parameters.size());
  const CatalogRobot& panda = two.robots()[1];
  // The shelf has a start for each robot; the bin has none (home).
  const json scenes = scenesJson(two, panda);
  EXPECT_EQ(scenes.at("robot"), "panda_gripper");
  EXPECT_EQ(scenes.at("scenes")[1].at("name"), "shelf");
  EXPECT_EQ(scenes.at("scenes")[1].at("start").size(), 8u);
  EXPECT_TRUE(scenes.at("scenes")[0].at("start").is_null());
  // Graspability is the Panda's: its own numbers, not the SDH's.
  const json objects = objectsJson(two, panda);
  EXPECT_EQ(objects.at("robot"), "panda_gripper");
  const json& mug = objects.at("objects")[2];
  EXPECT_EQ(mug.at("graspability").at("stable"), panda.graspability.at("mug").stable);
  EXPECT_NE(mug.at("graspability"),
            objectsJson(two, two.robots()[0]).at("objects")[2].at("graspability"));
}

TEST(CatalogJson, ParametersListEveryDeclaredOne) {
  const json p = plannerParametersJson(test::serviceCatalog().robots().front());
  EXPECT_EQ(p.size(), test::serviceCatalog().plannerParameters().size());
  bool found = false;
  for (const json& item : p)
    if (item.at("name") == "p_max") {
      found = true;
      EXPECT_EQ(item.at("default"), "0.9");
    }
  EXPECT_TRUE(found);
}

TEST(CatalogJson, GraspQualityAsHftsQuality) {
  const json q = graspQualityJson({{"contacts", kContacts}}, test::serviceCatalog());
  EXPECT_NEAR(q.at("epsilon").get<double>(), 0.275925155686099, 1e-12);
}

TEST(CatalogJson, GraspQualityOfAnObjectUsesItsCentreAndRho) {
  const db::ObjectDatabase& mug = *test::serviceCatalog().world().object("mug");
  grasp::GraspQualityRequest r;
  r.positions.resize(3, 3);
  r.normals.resize(3, 3);
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      r.positions(k, i) =
          kContacts[static_cast<std::size_t>(i)]["position"][static_cast<std::size_t>(k)];
      r.normals(k, i) =
          kContacts[static_cast<std::size_t>(i)]["normal"][static_cast<std::size_t>(k)];
    }
  r.center = mug.geometry.center_of_mass;
  r.torque_scale = mug.geometry.rho;
  const json q =
      graspQualityJson({{"contacts", kContacts}, {"object", "mug"}}, test::serviceCatalog());
  EXPECT_EQ(q.at("epsilon").get<double>(), grasp::graspQuality(r).epsilon);
}

TEST(CatalogJson, GraspQualityErrorsNameTheField) {
  const auto fieldOf = [](const json& params) {
    try {
      graspQualityJson(params, test::serviceCatalog());
    } catch (const RpcError& e) {
      EXPECT_EQ(e.code(), ErrorCode::kInvalidParams);
      EXPECT_EQ(std::string(e.what()).rfind(e.field() + ": ", 0), 0u) << e.what();
      return e.field();
    }
    return std::string("accepted");
  };
  json bad = kContacts;
  bad[1]["normal"] = {0, 2, 0};
  EXPECT_EQ(fieldOf({{"contacts", bad}}), "contacts[1].normal");
  EXPECT_EQ(fieldOf({{"contacts", kContacts}, {"friction", -1}}), "friction");
  EXPECT_EQ(fieldOf({{"contacts", kContacts}, {"object", "teapot"}}), "object");
  EXPECT_EQ(fieldOf({{"contacts", kContacts}, {"object", "../mug"}}), "object");
  EXPECT_EQ(fieldOf({{"contacts", json::array()}}), "contacts");
  EXPECT_EQ(fieldOf({{"contacts", kContacts}, {"extra", 1}}), "extra");
}

}  // namespace
}  // namespace hfts::service
