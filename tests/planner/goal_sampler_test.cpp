#include "planner/goal_sampler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "table_mug.h"

namespace hfts::planner {
namespace {

int cacheIndexOf(const HftsGoalSampler& sampler, const grasp::HftsNode& node) {
  for (std::size_t n = 0; n < sampler.cache().size(); ++n)
    if (sampler.cache().node(static_cast<int>(n)).hfts == node) return static_cast<int>(n);
  return GoalHierarchyCache::kNone;
}

TEST(HftsGoalSampler, NullSpaceGivesTheOtherIkBranchesThenOtherHandPostures) {
  test::TableMug setup;
  HftsGoalSampler sampler(setup.context, {});
  const int handDofs = setup.world.robot().numHandDofs();
  int goals = 0, withOtherHands = 0;
  for (int call = 0; call < 400 && goals < 6; ++call) {
    const GoalSample goal = sampler.sample(setup.knowledge, [] { return false; });
    if (goal.kind != GoalKind::kGoal) continue;
    ++goals;
    SCOPED_TRACE("goal " + std::to_string(goals));
    const int n = cacheIndexOf(sampler, goal.node);
    ASSERT_NE(n, GoalHierarchyCache::kNone);
    ASSERT_FALSE(sampler.cache().node(n).other_hands_sampled);
    const auto firstRound = static_cast<std::size_t>(
        std::count_if(sampler.cache().node(n).configurations.begin(),
                      sampler.cache().node(n).configurations.end(),
                      [](const CachedConfiguration& c) { return c.goal; }));
    std::vector<CachedConfiguration> handed;
    while (const CachedConfiguration* c = sampler.sampleNullSpace(n)) handed.push_back(*c);
    EXPECT_EQ(sampler.sampleNullSpace(n), nullptr);  // used up, and stays so
    EXPECT_TRUE(sampler.cache().node(n).other_hands_sampled);
    ASSERT_GE(handed.size(), firstRound - 1);  // every other IK branch first
    std::vector<Eigen::VectorXd> seen{goal.configuration};
    for (std::size_t i = 0; i < handed.size(); ++i) {
      const CachedConfiguration& c = handed[i];
      EXPECT_TRUE(c.goal && c.returned && c.collision_free);
      EXPECT_LE(c.fingertip_error, setup.context.max_fingertip_error);
      EXPECT_FALSE(setup.checker.inCollision(c.pregrasp)) << i;
      EXPECT_TRUE(std::none_of(seen.begin(), seen.end(),
                               [&](const Eigen::VectorXd& q) { return q == c.pregrasp; }))
          << "configuration " << i << " handed out twice";
      seen.push_back(c.pregrasp);
      const bool otherHand =
          (c.grasp.tail(handDofs) - goal.grasp.tail(handDofs)).cwiseAbs().maxCoeff() > 1e-9;
      EXPECT_EQ(otherHand, i + 1 >= firstRound) << i << ": IK branches come before other hands";
    }
    withOtherHands += handed.size() + 1 > firstRound;
  }
  EXPECT_GE(goals, 6);
  EXPECT_GE(withOtherHands, 1) << "no goal grasp had another hand posture";
}

TEST(HftsGoalSampler, NoNullSpaceWithoutAGoal) {
  test::TableMug setup;
  HftsGoalSampler sampler(setup.context, {});
  EXPECT_EQ(sampler.sampleNullSpace(GoalHierarchyCache::kNone), nullptr);
  EXPECT_EQ(sampler.sampleNullSpace(sampler.cache().root()), nullptr);
  for (int call = 0; call < 20; ++call) sampler.sample(setup.knowledge, [] { return false; });
  for (std::size_t n = 1; n < sampler.cache().size(); ++n) {
    const CacheNode& node = sampler.cache().node(static_cast<int>(n));
    if (std::any_of(node.configurations.begin(), node.configurations.end(),
                    [](const CachedConfiguration& c) { return c.goal; }))
      continue;
    EXPECT_EQ(sampler.sampleNullSpace(static_cast<int>(n)), nullptr);
    EXPECT_FALSE(node.other_hands_sampled) << "searched other hands of a grasp without a goal";
  }
}

TEST(HftsGoalSampler, AGrippersPhiTurnsThePalmForEveryNodeButTheUnstableLeaves) {
  const robot::RobotModel panda =
      robot::RobotModel::load(test::sourcePath("robots/panda_gripper/panda_gripper.json"));
  const PlanningWorld world(panda, grasp::buildHandMap(panda, grasp::handMapOptions(panda)),
                            test::bundledObjects());
  const robot::Scene scene = test::TableMug::table();
  const db::ObjectDatabase& mug = *world.object("mug");
  robot::CollisionChecker checker(world.collisionModel(), scene, &mug.geometry,
                                  world.collisionMesh("mug"));
  const grasp::HftsSpace space(mug, 2);
  grasp::GraspObjective objective(space, world.handMap(), grasp::objectiveOptions(panda));
  grasp::GraspConfigurator configurator(world.robot(), world.ik(), world.thoroughHandMap(), checker,
                                        scene.target_pose, scene.robot_base);
  configurator.setTurns(8);
  std::mt19937_64 rng(3);
  HftsGoalSampler sampler({&space, &objective, &configurator, &checker, &rng, MotionCheck{}}, {});
  const test::StartOnly knowledge(checker.metric(), world.robot().home());
  for (int call = 0; call < 30; ++call) sampler.sample(knowledge, [] { return false; });
  const GoalSamplerStatistics& s = sampler.statistics();
  ASSERT_GT(s.rejected.unstable, 0u);
  ASSERT_GT(s.configured_nodes, s.rejected.unstable);
  EXPECT_EQ(s.turned_nodes + s.rejected.unstable, s.configured_nodes);
}

TEST(HftsGoalSampler, AHandWithoutAFreeTurnTurnsNothing) {
  test::TableMug setup;
  setup.configurator.setTurns(8);
  HftsGoalSampler sampler(setup.context, {});
  for (int call = 0; call < 10; ++call) sampler.sample(setup.knowledge, [] { return false; });
  EXPECT_GT(sampler.statistics().configured_nodes, 0u);
  EXPECT_EQ(sampler.statistics().turned_nodes, 0u);
}

// Algorithm 2: what one call of SAMPLEGOAL may do.

const std::function<bool()> kNever = [] { return false; };
const std::function<bool()> kAlways = [] { return true; };

/// Whether a call could have taken Alg. 2 lines 7-13 (which spend the
/// budget without a new child): an inner cached node whose children are
/// all cached.
bool someInnerNodeFullyCovered(const GoalHierarchyCache& cache) {
  for (std::size_t n = 0; n < cache.size(); ++n)
    if (!cache.isLeaf(static_cast<int>(n)) && cache.coverage(static_cast<int>(n)) >= 1.0)
      return true;
  return false;
}

/// The table with the mug and nothing else on it: more of the sampled
/// configurations are free (the other objects block many).
test::TableMug bareTable() {
  robot::Scene scene = test::TableMug::table();
  scene.obstacles.erase(std::remove_if(scene.obstacles.begin(), scene.obstacles.end(),
                                       [](const robot::Obstacle& o) { return o.name != "table"; }),
                        scene.obstacles.end());
  return test::TableMug(scene);
}

class KappaBudget : public ::testing::TestWithParam<int> {};

TEST_P(KappaBudget, OneCallMakesAtMostKappaNewChildren) {
  // Alg. 2 line 3: each new child (line 17) costs one of kappa samples; so
  // does a failed null-space sample (line 13), descending costs nothing.
  const int kappa = GetParam();
  test::TableMug setup = bareTable();
  HftsGoalSamplerOptions options;
  options.samples = kappa;
  HftsGoalSampler sampler(setup.context, options);
  int fullBudget = 0;
  for (int call = 0; call < 25; ++call) {
    SCOPED_TRACE("call " + std::to_string(call));
    const std::size_t cached = sampler.cache().size();
    const std::uint64_t explored = sampler.statistics().nodes_explored;
    const GoalSample s = sampler.sample(setup.knowledge, kNever);
    const auto made = static_cast<int>(sampler.cache().size() - cached);
    EXPECT_EQ(sampler.statistics().nodes_explored - explored, static_cast<std::uint64_t>(made));
    EXPECT_LE(made, kappa);
    // Without a goal to return and without lines 7-13, the whole budget
    // goes into new children.
    if (s.kind != GoalKind::kGoal && !someInnerNodeFullyCovered(sampler.cache())) {
      EXPECT_EQ(made, kappa);
    }
    fullBudget += made == kappa;
  }
  EXPECT_GE(fullBudget, 5);
}

INSTANTIATE_TEST_SUITE_P(Kappa, KappaBudget, ::testing::Values(1, 2, 4));

/// Configurations in lexicographic order.
std::vector<Eigen::VectorXd> sorted(std::vector<Eigen::VectorXd> v) {
  std::sort(v.begin(), v.end(), [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return std::lexicographical_compare(a.data(), a.data() + a.size(), b.data(),
                                        b.data() + b.size());
  });
  return v;
}

TEST(HftsGoalSampler, WithoutAGoalACallReturnsAnApproximateGoalTakenOutOfA) {
  // Alg. 2 lines 25-26 put the free configuration of each new child without
  // a goal into A; lines 28-32 return one of A when the call finds no goal,
  // removing it.
  test::TableMug setup = bareTable();
  HftsGoalSampler sampler(setup.context, {});
  int approximate = 0;
  for (int call = 0; call < 40; ++call) {
    SCOPED_TRACE("call " + std::to_string(call));
    std::vector<Eigen::VectorXd> pool = sampler.approximateGoals();
    const std::size_t cached = sampler.cache().size();
    const GoalSamplerStatistics before = sampler.statistics();
    const GoalSample s = sampler.sample(setup.knowledge, kNever);
    for (std::size_t n = cached; n < sampler.cache().size(); ++n) {
      const auto& configurations = sampler.cache().node(static_cast<int>(n)).configurations;
      if (!configurations.empty() && configurations.front().collision_free &&
          std::none_of(configurations.begin(), configurations.end(),
                       [](const CachedConfiguration& c) { return c.goal; }))
        pool.push_back(configurations.front().pregrasp);
    }
    // A is a set (line 28 draws from it at random): compared as one.
    const std::vector<Eigen::VectorXd> after = sorted(sampler.approximateGoals());
    if (s.kind == GoalKind::kGoal) {
      EXPECT_EQ(after, sorted(pool));
      continue;
    }
    if (s.kind == GoalKind::kNone) {
      EXPECT_TRUE(pool.empty());
      EXPECT_TRUE(after.empty());
      continue;
    }
    ++approximate;
    EXPECT_EQ(sampler.statistics().approximate_goals, before.approximate_goals + 1);
    EXPECT_FALSE(setup.checker.inCollision(s.configuration));
    const auto taken = std::find(pool.begin(), pool.end(), s.configuration);
    ASSERT_NE(taken, pool.end()) << "not from A";
    pool.erase(taken);
    EXPECT_EQ(after, sorted(pool));
    // The node it came from, whose first configuration it is.
    const int n = cacheIndexOf(sampler, s.node);
    ASSERT_NE(n, GoalHierarchyCache::kNone);
    EXPECT_EQ(sampler.cache().node(n).configurations.front().pregrasp, s.configuration);
  }
  EXPECT_GE(approximate, 5);  // 11 of 40
}

TEST(HftsGoalSampler, StoppedCallsDrainAThenReturnNothing) {
  // A call stopped before its search does lines 28-32 only: each returns
  // an element of A and removes it, until A is empty and the answer is
  // "bottom" (kNone). (A grows when calls add more free configurations
  // than they take: a large kappa.)
  test::TableMug setup = bareTable();
  HftsGoalSamplerOptions options;
  options.samples = 16;
  HftsGoalSampler sampler(setup.context, options);
  // How many calls that takes depends on the mug's database: 93 with the
  // default filters (19 with the filters of before they were scaled to the
  // fingertip, 6 with filters scaled to the SDH's own pads).
  for (int call = 0; call < 500 && sampler.approximateGoals().size() < 4; ++call)
    sampler.sample(setup.knowledge, kNever);
  std::vector<Eigen::VectorXd> a = sampler.approximateGoals();
  ASSERT_GE(a.size(), 4u);
  const std::size_t held = a.size();
  const std::size_t cached = sampler.cache().size();
  const GoalSamplerStatistics before = sampler.statistics();
  while (!a.empty()) {
    const GoalSample s = sampler.sample(setup.knowledge, kAlways);
    ASSERT_EQ(s.kind, GoalKind::kApproximate);
    const auto taken = std::find(a.begin(), a.end(), s.configuration);
    ASSERT_NE(taken, a.end()) << "not from A";
    a.erase(taken);
    EXPECT_EQ(sampler.approximateGoals(), a);
    EXPECT_FALSE(setup.checker.inCollision(s.configuration));
  }
  for (int more = 0; more < 3; ++more) {
    const GoalSample s = sampler.sample(setup.knowledge, kAlways);
    EXPECT_EQ(s.kind, GoalKind::kNone);
    EXPECT_EQ(s.configuration.size(), 0);
  }
  EXPECT_EQ(sampler.cache().size(), cached) << "a stopped call searched";
  EXPECT_EQ(sampler.statistics().nodes_explored, before.nodes_explored);
  EXPECT_EQ(sampler.statistics().approximate_goals, before.approximate_goals + held);
  EXPECT_EQ(sampler.statistics().calls, before.calls + held + 3);
}

TEST(HftsGoalSampler, NothingWhenAIsEmptyAndNoGoalIsFound) {
  // The mug 3 m away: no grasp has an IK solution, so no child brings a
  // goal or a free configuration; every call spends its budget on new
  // children and returns "bottom".
  robot::Scene scene = test::TableMug::table();
  scene.target_pose = Eigen::Translation3d(3.0, 0.0, 0.0);
  test::TableMug setup(scene);
  HftsGoalSampler sampler(setup.context, {});
  for (int call = 0; call < 5; ++call) {
    const std::size_t cached = sampler.cache().size();
    const GoalSample s = sampler.sample(setup.knowledge, kNever);
    EXPECT_EQ(s.kind, GoalKind::kNone);
    EXPECT_EQ(s.configuration.size(), 0);
    EXPECT_TRUE(sampler.approximateGoals().empty());
    EXPECT_EQ(sampler.cache().size() - cached, 4u);  // kappa
  }
  const GoalSamplerStatistics& stats = sampler.statistics();
  EXPECT_EQ(stats.calls, 5u);
  EXPECT_EQ(stats.configured_nodes, 20u);
  EXPECT_EQ(stats.kinematic_solutions, 0u);
  EXPECT_EQ(stats.valid_goals + stats.approximate_goals, 0u);
}

TEST(HftsGoalSampler, OtherPosturesAreTriedForStableLeavesWithoutAGoal) {
  for (const bool other : {false, true}) {
    SCOPED_TRACE(other ? "other_postures on" : "other_postures off");
    test::TableMug setup;
    setup.context.other_postures = other;
    HftsGoalSampler sampler(setup.context, {});
    for (int call = 0; call < 60; ++call) sampler.sample(setup.knowledge, [] { return false; });
    int stableWithoutGoal = 0;
    for (std::size_t n = 1; n < sampler.cache().size(); ++n) {
      const CacheNode& node = sampler.cache().node(static_cast<int>(n));
      const bool goal = std::any_of(node.configurations.begin(), node.configurations.end(),
                                    [](const CachedConfiguration& c) { return c.goal; });
      if (!sampler.cache().isLeaf(static_cast<int>(n)) || !(node.quality > 0.0) || goal) continue;
      ++stableWithoutGoal;
      EXPECT_EQ(node.other_hands_sampled, other) << "node " << n;
    }
    EXPECT_GT(stableWithoutGoal, 0);
  }
}

}  // namespace
}  // namespace hfts::planner
