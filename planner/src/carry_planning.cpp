#include "carry_planning.h"

#include <ompl/base/ProblemDefinition.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "motion_goal_sampler.h"
#include "robot/kinematics.h"
#include "robot/sensed_scene.h"

namespace hfts::planner {

robot::Scene obstaclesOf(const robot::Scene& scene) {
  robot::Scene out = robot::heldScene(scene);
  out.target_rest_on.clear();
  return out;
}

CarryPlanning::CarryPlanning(const Problem& p, const Hold& hold, const Eigen::VectorXd& grasp,
                             double clearance)
    : world_(carryWorld(p.world, hold, grasp)),
      settings_(p.settings),
      checker_(std::make_shared<const robot::CollisionScene>(
          world_->collisionModel(), obstaclesOf(p.scene), nullptr, nullptr, nullptr, clearance)) {
  settings_.path.clearance = clearance;
  checker_.setSphereTier(settings_.execution.sphere_tier);
  si_ = makeSpaceInformation(world_->robot(), checker_, kTreeResolution);
  planner_ = Problem::plannerFor(si_, settings_);
  planner_->setCertification(settings_.path.certify ? &world_->motionBound() : nullptr);
  planner_->setLastSegmentRule(robot::CertifyRule::kTransit);
  planner_->setSeed(p.seed);
}

std::optional<std::vector<Eigen::VectorXd>> CarryPlanning::solve(
    const Eigen::VectorXd& start, GoalSampler& sampler,
    const ob::PlannerTerminationCondition& ptc) {
  auto pdef = std::make_shared<ob::ProblemDefinition>(si_);
  ob::ScopedState<> startState(si_);
  weightedSpace(si_).fromVector(start, startState.get());
  pdef->addStartState(startState);
  pdef->setGoal(std::make_shared<GraspGoal>(si_, sampler));
  planner_->setProblemDefinition(pdef);
  planner_->setup();
  if (planner_->solve(ptc) != ob::PlannerStatus::EXACT_SOLUTION) return std::nullopt;
  return planner_->solutionPath();
}

namespace {

/// `path` with waypoints added so that no joint moves more than `step`
/// (rad or m) between two.
std::vector<Eigen::VectorXd> interpolated(const std::vector<Eigen::VectorXd>& path, double step) {
  std::vector<Eigen::VectorXd> out{path.front()};
  for (std::size_t i = 1; i < path.size(); ++i) {
    const double largest = (path[i] - path[i - 1]).cwiseAbs().maxCoeff();
    const int pieces = std::max(1, static_cast<int>(std::ceil(largest / step)));
    for (int k = 1; k <= pieces; ++k) {
      const double f = static_cast<double>(k) / pieces;
      out.push_back((1 - f) * path[i - 1] + f * path[i]);
    }
  }
  return out;
}

/// The palm poses a planned lift may end at (plannedLift).
std::vector<MotionGoal> liftGoals(const robot::RobotModel& robot, const Eigen::Isometry3d& base,
                                  const Eigen::VectorXd& grasp, double height) {
  // A ball of this radius above the lifted height: the palm rises by
  // `height` at least.
  constexpr double kTolerance = 0.03;
  constexpr double kTurn = 20.0 * M_PI / 180.0;
  const Eigen::Isometry3d palm =
      base * robot::forwardKinematics(robot, grasp)[static_cast<std::size_t>(robot.palmLink())];
  const auto horizontal = [](Eigen::Vector3d v) {
    v.z() = 0.0;
    return v.norm() > 1e-6 ? Eigen::Vector3d(v.normalized()) : Eigen::Vector3d::Zero();
  };
  const Eigen::Vector3d aside[] = {horizontal(base.translation() - palm.translation()),
                                   horizontal(-palm.linear().col(2)),
                                   Eigen::Vector3d::UnitX(),
                                   -Eigen::Vector3d::UnitX(),
                                   Eigen::Vector3d::UnitY(),
                                   -Eigen::Vector3d::UnitY()};
  const Eigen::Vector3d above =
      palm.translation() + (height + kTolerance) * Eigen::Vector3d::UnitZ();
  std::vector<MotionGoal> goals;
  const auto add = [&](const Eigen::Vector3d& at) {
    PoseGoal goal;
    goal.pose = palm;
    goal.pose.translation() = at;
    goal.position_tolerance = kTolerance;
    goal.orientation_tolerance = kTurn;
    goals.emplace_back(goal);
  };
  add(above);
  for (const double distance : {0.15, 0.3})
    for (const Eigen::Vector3d& direction : aside)
      if (!direction.isZero()) add(above + distance * direction);
  return goals;
}

}  // namespace

std::optional<LiftPath> plannedLift(const Problem& p, const Hold& hold,
                                    const Eigen::VectorXd& grasp, double height,
                                    const ob::PlannerTerminationCondition& ptc) {
  CarryPlanning carry(p, hold, grasp, 0.0);
  if (carry.checker().inCollision(grasp)) return std::nullopt;
  const robot::RobotModel& robot = carry.world().robot();
  MotionGoalSampler sampler(
      carry.world().ik(), carry.checker(), carry.planner().rng(), p.scene.robot_base,
      checkGoals(robot, liftGoals(robot, p.scene.robot_base, grasp, height), grasp), grasp);
  const std::optional<std::vector<Eigen::VectorXd>> path =
      carry.solve(grasp, sampler,
                  ob::plannerOrTerminationCondition(
                      ptc, ob::timedPlannerTerminationCondition(kPlannedLiftTime)));
  if (!path) return std::nullopt;
  return LiftPath{interpolated(*path, 0.01), "planned"};
}

}  // namespace hfts::planner
