#include "planner/goal_sampler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "plan_checks.h"

namespace hfts::planner {
namespace {

/// Free-space knowledge of a planner that has explored nothing but its
/// start: Gamma is the distance to the start, nothing is non-connected.
class StartOnly : public FreeSpaceDistances {
 public:
  StartOnly(const CollisionChecker& metric, Eigen::VectorXd start)
      : metric_(metric), start_(std::move(start)) {}
  double toNonConnected(const Eigen::VectorXd& /*q*/) const override {
    return std::numeric_limits<double>::infinity();
  }
  double toConnected(const Eigen::VectorXd& q) const override {
    return metric_.distance(q, start_);
  }

 private:
  const CollisionChecker& metric_;
  Eigen::VectorXd start_;
};

/// The table scene with the mug: the pieces planGrasp gives a sampler.
struct TableMug {
  const PlanningWorld& world = test::bundledWorld();
  const db::ObjectDatabase& object = *world.object("mug");
  Scene scene = loadScene(test::sourcePath("objects/scenes/table.json"));
  CollisionChecker checker{world.robot(), scene, &object.geometry, world.collisionMesh("mug")};
  HftsSpace space{object, static_cast<int>(world.robot().fingertips().size())};
  GraspObjective objective{space, world.handMap()};
  GraspConfigurator configurator{world.robot(), world.ik(),        world.thoroughHandMap(),
                                 checker,       scene.target_pose, scene.robot_base};
  std::mt19937_64 rng{5};
  GoalSamplingContext context{&space, &objective, &configurator, &checker, &rng};
  StartOnly knowledge{checker, scene.start.value_or(world.robot().home())};
};

int cacheIndexOf(const HftsGoalSampler& sampler, const HftsNode& node) {
  for (std::size_t n = 0; n < sampler.cache().size(); ++n)
    if (sampler.cache().node(static_cast<int>(n)).hfts == node) return static_cast<int>(n);
  return GoalHierarchyCache::kNone;
}

TEST(HftsGoalSampler, NullSpaceGivesTheOtherIkBranchesThenOtherHandPostures) {
  TableMug setup;
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
  TableMug setup;
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

}  // namespace
}  // namespace hfts::planner
