#include "planner/multi_tree_cbirrt.h"

#include <gtest/gtest.h>

#include <ompl/base/PlannerData.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/terminationconditions/IterationTerminationCondition.h>

#include "planner/configuration_space.h"
#include "table_mug.h"

namespace hfts::planner {
namespace {

namespace ob = ompl::base;

TEST(MultiTreeCBiRRT, PlannerDataHoldsEveryTreeNodeWithItsConfiguration) {
  test::TableMug setup;
  HftsGoalSampler sampler(setup.context, {});
  const auto si = makeSpaceInformation(setup.world.robot(), setup.checker, 0.02);
  auto planner = std::make_shared<MultiTreeCBiRRT>(si);
  const auto& space = *si->getStateSpace()->as<WeightedStateSpace>();
  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<> start(si);
  space.fromVector(setup.start, start.get());
  pdef->addStartState(start);
  pdef->setGoal(std::make_shared<GraspGoal>(si, sampler));
  planner->setProblemDefinition(pdef);
  planner->setSeed(3);
  planner->setup();
  // Stopped early, so that the trees are there to look at: no path yet.
  ob::IterationTerminationCondition iterations(300);
  planner->solve(ob::PlannerTerminationCondition(iterations));
  const TreeStatistics& stats = planner->statistics();
  ASSERT_GT(stats.forward_tree_size, 1u);
  ASSERT_GT(stats.backward_tree_nodes, 0u) << "no backward tree in 300 iterations";

  ob::PlannerData data(si);
  planner->getPlannerData(data);
  EXPECT_EQ(data.numVertices(), stats.forward_tree_size + stats.backward_tree_nodes);
  EXPECT_EQ(data.numStartVertices(), 1u);
  EXPECT_GE(data.numGoalVertices(), 1u);
  // A forest: one edge into every node but the roots.
  EXPECT_EQ(data.numEdges(), data.numVertices() - data.numStartVertices() - data.numGoalVertices());
  EXPECT_EQ(space.toVector(data.getStartVertex(0).getState()), setup.start);
  for (unsigned v = 0; v < data.numVertices(); ++v)
    EXPECT_TRUE(si->isValid(data.getVertex(v).getState())) << "vertex " << v;
  // Asked again: the same states (made once per node).
  ob::PlannerData again(si);
  planner->getPlannerData(again);
  ASSERT_EQ(again.numVertices(), data.numVertices());
  EXPECT_EQ(again.getStartVertex(0).getState(), data.getStartVertex(0).getState());
}

}  // namespace
}  // namespace hfts::planner
