#include "service/planning_catalog.h"

#include <gtest/gtest.h>

#include "grasp/hand_reachability.h"
#include "hfts_db/hand_map.h"
#include "robot_fixture.h"
#include "service_catalog.h"
#include "test_meshes.h"

namespace hfts::service {
namespace {

/// A database directory with the mug, a broken file and the hand map, and
/// a scene directory with the bundled table plus a broken scene.
struct Sources {
  test::TempDir dir;
  CatalogSources sources;
  Sources() {
    std::filesystem::create_directories(dir / "db");
    std::filesystem::create_directories(dir / "scenes");
    db::saveObjectDatabase(test::sceneTargetObjects().at("mug"), dir / "db" / "mug.h5");
    db::saveHandMap(grasp::buildHandMap(test::kr5Sdh()), dir / "db" / "kr5_sdh_hand_map.h5");
    test::writeText(dir / "db" / "broken.h5", "not hdf5");
    std::filesystem::copy_file(test::sourcePath("objects/scenes/table.json"),
                               dir / "scenes" / "kitchen_table.json");
    test::writeText(dir / "scenes" / "broken.json", "{\"name\": \"broken\"}");
    sources = {{test::sourcePath("robots/kr5_sdh/kr5_sdh.json")}, dir / "db", dir / "scenes"};
  }
};

TEST(PlanningCatalog, LoadsTheWorldAndNamesScenesByFile) {
  const Sources s;
  const auto catalog = PlanningCatalog::load(s.sources);
  EXPECT_EQ(catalog->world().objectNames(), std::vector<std::string>{"mug"});
  ASSERT_EQ(catalog->scenes().size(), 1u);
  const robot::Scene* scene = catalog->scene("kitchen_table");
  ASSERT_NE(scene, nullptr);
  EXPECT_EQ(scene->name, "kitchen_table") << "not the file's 'table'";
  EXPECT_EQ(scene->target_object, "mug");
  EXPECT_EQ(catalog->scene("table"), nullptr);
  EXPECT_EQ(catalog->sceneDir(), s.dir / "scenes");
  EXPECT_FALSE(catalog->plannerParameters().empty());
  EXPECT_EQ(catalog->robot().numDofs(), 13);
}

TEST(PlanningCatalog, ReportsWhatItSkipped) {
  const Sources s;
  const auto catalog = PlanningCatalog::load(s.sources);
  ASSERT_EQ(catalog->skipped().size(), 2u);
  EXPECT_NE(catalog->skipped()[0].find("broken.h5"), std::string::npos);
  EXPECT_NE(catalog->skipped()[1].find("broken.json"), std::string::npos);
}

TEST(PlanningCatalog, MissingDirectoriesOrMapThrowNamingThem) {
  Sources s;
  CatalogSources noScenes = s.sources;
  noScenes.scene_dir = s.dir / "nowhere";
  test::expectErrorMentioning<std::runtime_error>([&] { PlanningCatalog::load(noScenes); },
                                                  {"nowhere", "does not exist"});
  std::filesystem::remove(s.dir / "db" / "kr5_sdh_hand_map.h5");
  test::expectErrorMentioning<std::runtime_error>([&] { PlanningCatalog::load(s.sources); },
                                                  {"kr5_sdh_hand_map.h5"});
}

const std::filesystem::path kPandaConfig = "robots/panda_gripper/panda_gripper.json";

TEST(PlanningCatalog, ServesSeveralRobotsOverTheSameObjects) {
  Sources s;
  const robot::RobotModel panda = robot::RobotModel::load(test::sourcePath(kPandaConfig));
  db::saveHandMap(grasp::buildHandMap(panda, grasp::handMapOptions(panda)),
                  s.dir / "db" / "panda_gripper_hand_map.h5");
  s.sources.robot_configs.push_back(test::sourcePath(kPandaConfig));
  const auto catalog = PlanningCatalog::load(s.sources);
  EXPECT_EQ(catalog->robotNames(), (std::vector<std::string>{"kr5_sdh", "panda_gripper"}));
  EXPECT_EQ(catalog->robot().name(), "kr5_sdh") << "the first config is the default";
  const CatalogRobot* second = catalog->findRobot("panda_gripper");
  ASSERT_NE(second, nullptr);
  EXPECT_EQ(second->model().numDofs(), 8);
  EXPECT_EQ(second->model().fingertips().size(), 2u);
  EXPECT_EQ(second->world->objects(), catalog->world().objects()) << "objects loaded once";
  EXPECT_EQ(catalog->findRobot("ur5e"), nullptr);
  ASSERT_EQ(catalog->skipped().size(), 2u) << "the broken database is reported once";
  // Defaults and graspability are the robot's own.
  const auto defaultOf = [](const CatalogRobot& r, const std::string& name) {
    for (const planner::PlannerParameterInfo& p : r.parameters)
      if (p.name == name) return p.default_value;
    return std::string("missing");
  };
  EXPECT_EQ(std::stod(defaultOf(catalog->robots().front(), "max_fingertip_error")), 0.008);
  EXPECT_EQ(std::stod(defaultOf(*second, "max_fingertip_error")), 0.005);
  EXPECT_EQ(defaultOf(*second, "fit_check"), "1");
  EXPECT_EQ(std::stod(defaultOf(*second, "fit_clearance")), 0.0025) << "the Panda config's";
  EXPECT_EQ(std::stod(defaultOf(catalog->robots().front(), "fit_clearance")), 0.0);
  EXPECT_EQ(second->graspability.at("mug").sampled, 1000);
  EXPECT_NE(second->graspability.at("mug").stable, catalog->graspability("mug").stable);
}

TEST(PlanningCatalog, TwoConfigsOfOneRobotOrAMissingMapAreNamed) {
  Sources s;
  s.sources.robot_configs.push_back(test::sourcePath("robots/kr5_sdh/kr5_sdh.json"));
  test::expectErrorMentioning<std::runtime_error>([&] { PlanningCatalog::load(s.sources); },
                                                  {"a second robot named 'kr5_sdh'"});
  s.sources.robot_configs.back() = test::sourcePath(kPandaConfig);
  test::expectErrorMentioning<std::runtime_error>(
      [&] { PlanningCatalog::load(s.sources); },
      {"panda_gripper_hand_map.h5", "hfts-preprocess --hand"});
  s.sources.robot_configs.clear();
  test::expectErrorMentioning<std::runtime_error>([&] { PlanningCatalog::load(s.sources); },
                                                  {"no robot config"});
}

}  // namespace
}  // namespace hfts::service
