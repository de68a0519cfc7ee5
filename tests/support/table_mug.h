#pragma once
// The table scene with the mug, taken apart as planGrasp builds it: for
// tests of the goal sampler and the multi-tree planner on their own.

#include <limits>
#include <random>

#include "plan_checks.h"
#include "planner/goal_sampler.h"

namespace hfts::test {

/// Free-space knowledge of a planner that has explored nothing but its
/// start: Gamma is the distance to the start, nothing is non-connected.
class StartOnly : public planner::FreeSpaceDistances {
 public:
  StartOnly(const robot::ConfigurationMetric& metric, Eigen::VectorXd start)
      : metric_(metric), start_(std::move(start)) {}
  double toNonConnected(const Eigen::VectorXd& /*q*/) const override {
    return std::numeric_limits<double>::infinity();
  }
  double toConnected(const Eigen::VectorXd& q) const override {
    return metric_.distance(q, start_);
  }

 private:
  const robot::ConfigurationMetric& metric_;
  Eigen::VectorXd start_;
};

/// The table scene with the mug: the pieces planGrasp gives a sampler.
struct TableMug {
  TableMug() = default;
  /// The same pieces in another scene (e.g. table() changed).
  explicit TableMug(robot::Scene s) : scene(std::move(s)) {}
  static robot::Scene table() { return robot::loadScene(sourcePath("objects/scenes/table.json")); }

  const planner::PlanningWorld& world = bundledWorld();
  const db::ObjectDatabase& object = *world.object("mug");
  robot::Scene scene = table();
  robot::CollisionChecker checker{world.collisionModel(), scene, &object.geometry,
                                  world.collisionMesh("mug"), world.surface("mug")};
  grasp::HftsSpace space{object, static_cast<int>(world.robot().fingertips().size())};
  grasp::GraspObjective objective{space, world.handMap()};
  grasp::HandCloser closer{world.collisionModel(), *world.surface("mug")};
  grasp::GraspConfigurator configurator{world.robot(), world.ik(),        world.thoroughHandMap(),
                                        checker,       scene.target_pose, scene.robot_base,
                                        &closer};
  std::mt19937_64 rng{5};
  planner::GoalSamplingContext context{&space,   &objective, &configurator,
                                       &checker, &rng,       planner::MotionCheck{}};
  Eigen::VectorXd start = scene.startFor(world.robot().name()).value_or(world.robot().home());
  StartOnly knowledge{checker.metric(), start};
};

}  // namespace hfts::test
