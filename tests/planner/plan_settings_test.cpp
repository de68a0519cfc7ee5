#include "planner/plan_settings.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "core/invalid_argument.h"
#include "panda_cube.h"
#include "plan_checks.h"
#include "planner/grasp_motion_planner.h"
#include "robot_fixture.h"

namespace hfts::planner {
namespace {

const robot::RobotModel& kr5() {
  return test::kr5Sdh();
}

std::string rejection(PlanSettings s, const std::string& name, const std::string& value) {
  try {
    setSetting(s, name, value);
  } catch (const InvalidArgument& e) {
    return e.what();
  }
  return "accepted";
}

TEST(PlanSettings, TheStructsHoldThePapersValues) {
  const PlanSettings s;
  EXPECT_EQ(s.paper.p_max, 0.9);  // Fig. 6
  EXPECT_EQ(s.paper.p_min, 0.01);
  EXPECT_EQ(s.paper.d_m, 0.4);
  EXPECT_EQ(s.paper.w_f, 0.5);
  EXPECT_EQ(s.paper.w_c, 4.0);
  EXPECT_EQ(s.paper.n_a, 20);
  EXPECT_EQ(s.paper.kappa, 4);
  EXPECT_EQ(s.paper.i_min, 20);
  EXPECT_EQ(s.paper.i_max, 100);
  EXPECT_EQ(s.paper.alpha, 1e-6);
  EXPECT_EQ(s.paper.p_w, 1.2);
  EXPECT_FALSE(s.paper.weight_arm.has_value());
}

TEST(PlanSettings, TheRobotsDefaultsAreThePlannersUnderItsConfig) {
  // Every kept addition is on for every hand (docs/planning.md, "What the
  // additions buy"); a config changes what it names (kr5_sdh.json's
  // fingertip tolerance), nothing else.
  for (const robot::RobotModel* robot : {&kr5(), &test::panda()}) {
    const PlanSettings s = defaultSettings(*robot);
    SCOPED_TRACE(robot->name());
    EXPECT_EQ(s.heuristics.p_local, 1.0);
    EXPECT_TRUE(s.heuristics.other_postures && s.heuristics.mask_contacts &&
                s.heuristics.unstable_by_reach && s.heuristics.fit_check);
    EXPECT_EQ(s.heuristics.palm_turns, 8);
    EXPECT_TRUE(s.goal.physics_check);
  }
  EXPECT_EQ(defaultSettings(kr5()).goal.max_fingertip_error, 0.008);
  EXPECT_EQ(defaultSettings(kr5()).heuristics.fit_clearance, 0.0);
  EXPECT_EQ(defaultSettings(test::panda()).goal.max_fingertip_error, 0.005);
  EXPECT_EQ(defaultSettings(test::panda()).heuristics.fit_clearance, 0.0025);
}

TEST(PlanSettings, ThePaperPresetTurnsEveryAdditionOff) {
  const PlanSettings s = defaultSettings(kr5(), PlannerPreset::kPaper);
  EXPECT_EQ(s.heuristics.p_local, 0.0);
  EXPECT_FALSE(s.heuristics.other_postures || s.heuristics.mask_contacts ||
               s.heuristics.unstable_by_reach || s.heuristics.fit_check);
  EXPECT_EQ(s.heuristics.palm_turns, 1);
  EXPECT_FALSE(s.goal.physics_check);
  // What a goal is stays: the config's fingertip tolerance is not an addition.
  EXPECT_EQ(s.goal.max_fingertip_error, 0.008);
}

TEST(PlanSettings, ARequestsParametersApplyOverItsTypedSettings) {
  PlanRequest r;
  r.settings = defaultSettings(kr5());
  r.settings->paper.p_max = 0.5;
  r.settings->heuristics.p_local = 0.1;
  r.parameters = {{"p_local", "0.3"}, {"physics_check", "0"}};
  r.iterations = 40;
  const PlanSettings s = resolveSettings(kr5(), r);
  EXPECT_EQ(s.paper.p_max, 0.5);
  EXPECT_EQ(s.heuristics.p_local, 0.3);
  EXPECT_FALSE(s.goal.physics_check);
  EXPECT_EQ(s.paper.decoupled_iterations, 40);
  // Without typed settings: the robot's defaults under the parameters.
  r.settings.reset();
  EXPECT_EQ(resolveSettings(kr5(), r).paper.p_max, 0.9);
  EXPECT_EQ(resolveSettings(kr5(), r).goal.max_fingertip_error, 0.008);
}

TEST(PlanSettings, BadValuesAreRejectedNamingTheParameter) {
  const PlanSettings s;
  EXPECT_EQ(rejection(s, "p_max", "1.5"), "parameters.p_max: must be in [0, 1], got 1.5");
  EXPECT_EQ(rejection(s, "kappa", "2.5"), "parameters.kappa: must be an integer, got '2.5'");
  EXPECT_EQ(rejection(s, "fit_check", "2"), "parameters.fit_check: must be in [0, 1], got 2");
  EXPECT_EQ(rejection(s, "teleport", "1"), "parameters.teleport: unknown planner parameter");
  PlanRequest r;
  r.settings = PlanSettings{};
  r.settings->paper.step_size = -1.0;  // typed settings are checked too
  try {
    resolveSettings(kr5(), r);
    ADD_FAILURE() << "accepted a negative step size";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.field(), "parameters.step_size");
  }
  r.settings = PlanSettings{};
  r.settings->paper.i_min = 50;
  r.settings->paper.i_max = 10;
  try {
    resolveSettings(kr5(), r);
    ADD_FAILURE() << "accepted i_min > i_max";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.field(), "parameters.i_min");
  }
  r.settings.reset();
  r.iterations = 0;
  try {
    resolveSettings(kr5(), r);
    ADD_FAILURE() << "accepted 0 iterations";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.field(), "iterations");
  }
  EXPECT_EQ(settingRange("p_goal_tree").high, 1.0);
  EXPECT_THROW(settingRange("teleport"), InvalidArgument);
}

TEST(PlanSettings, EverySettingIsListedByNameWithTheRobotsWeights) {
  const std::vector<PlannerParameterInfo> listed = describeSettings(defaultSettings(kr5()), kr5());
  EXPECT_EQ(listed.size(), 37u);
  const auto value = [&](const std::string& name) {
    const auto it = std::find_if(listed.begin(), listed.end(),
                                 [&](const PlannerParameterInfo& p) { return p.name == name; });
    return it == listed.end() ? std::string("missing") : it->default_value;
  };
  EXPECT_EQ(std::stod(value("weight_arm")), 1.0);
  EXPECT_EQ(std::stod(value("weight_hand")), 0.25);  // kr5_sdh.json's dof_weights
  EXPECT_EQ(std::stod(value("max_fingertip_error")), 0.008);
  EXPECT_EQ(value("threads"), "1");
}

TEST(PlanSettings, TypedSettingsAndTheSameParametersByNamePlanTheSamePath) {
  PlanRequest named = test::bundledSceneRequest("table", "mug", 3, PlanAlgorithm::kCoupled);
  named.parameters = {{"physics_check", "0"}, {"p_max", "0.8"}, {"local_radius", "0.5"}};
  PlanRequest typed = test::bundledSceneRequest("table", "mug", 3, PlanAlgorithm::kCoupled);
  typed.settings = defaultSettings(test::bundledWorld().robot());
  typed.settings->goal.physics_check = false;
  typed.settings->paper.p_max = 0.8;
  typed.settings->heuristics.local_radius = 0.5;
  const PlanResult a = planGrasp(test::bundledWorld(), named);
  const PlanResult b = planGrasp(test::bundledWorld(), typed);
  ASSERT_TRUE(a.success && b.success) << a.message << " / " << b.message;
  ASSERT_EQ(a.path.size(), b.path.size());
  for (std::size_t i = 0; i < a.path.size(); ++i) EXPECT_EQ(a.path[i], b.path[i]);
  EXPECT_EQ(a.stats.collision_checks, b.stats.collision_checks);
}

}  // namespace
}  // namespace hfts::planner
