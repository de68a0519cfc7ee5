#include "planner/goal_sampler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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
  GraspConfigurator configurator{world.robot(),     world.ik(),        world.thoroughHandMap(),
                                 checker,           scene.target_pose, scene.robot_base};
  std::mt19937_64 rng{5};
  GoalSamplingContext context{&space, &objective, &configurator, &checker, &rng};
  Eigen::VectorXd start = scene.start.value_or(world.robot().home());
};

TEST(HftsGoalSampler, ReturnsTheBestRatedIkBranchOfAGoalGrasp) {
  TableMug setup;
  HftsGoalSampler sampler(setup.context, {});
  const StartOnly knowledge(setup.checker, setup.start);
  const RatingWeights w;
  std::vector<Eigen::VectorXd> returned;
  int choices = 0;  // goals returned while the grasp had other branches left
  for (int call = 0; call < 300 && choices < 4; ++call) {
    const GoalSample s = sampler.sample(knowledge, [] { return false; });
    if (s.kind != GoalKind::kGoal) continue;
    // Eq. (4)'s rating of a configuration with A as the non-connected space.
    const auto rate = [&](const Eigen::VectorXd& q) {
      double omega = std::numeric_limits<double>::infinity();
      for (const Eigen::VectorXd& a : sampler.approximateGoals())
        omega = std::min(omega, setup.checker.distance(q, a));
      return w.w_f * std::exp(-omega) + w.w_c * std::exp(-knowledge.toConnected(q));
    };
    const GoalHierarchyCache& cache = sampler.cache();
    const CacheNode* node = nullptr;
    for (std::size_t n = 0; n < cache.size(); ++n)
      if (cache.node(static_cast<int>(n)).hfts == s.node) node = &cache.node(static_cast<int>(n));
    ASSERT_NE(node, nullptr) << "a goal outside the cache";
    const double got = rate(s.configuration);
    int candidates = 0;
    for (const CachedConfiguration& c : node->configurations) {
      const bool before = std::any_of(returned.begin(), returned.end(),
                                      [&](const Eigen::VectorXd& q) { return q == c.pregrasp; });
      if (!c.goal || before) continue;
      ++candidates;
      EXPECT_GE(got, rate(c.pregrasp)) << "call " << call << ": a better-rated branch was left";
    }
    if (candidates > 1) ++choices;
    returned.push_back(s.configuration);
  }
  EXPECT_GE(choices, 4) << "too few grasps with several goal branches to test the choice";
}

}  // namespace
}  // namespace hfts::planner
