#include "motion_goal_sampler.h"

#include <cmath>
#include <limits>

namespace hfts::planner {

MotionGoalSampler::MotionGoalSampler(const robot::ArmIk& ik, robot::CollisionChecker& checker,
                                     std::mt19937_64& rng, const Eigen::Isometry3d& base,
                                     std::vector<MotionGoal> goals, Eigen::VectorXd start)
    : ik_(ik),
      checker_(checker),
      rng_(rng),
      baseInverse_(base.inverse()),
      goals_(std::move(goals)),
      start_(std::move(start)),
      drawn_(goals_.size(), false) {
  for (std::size_t g = 0; g < goals_.size(); ++g) {
    const auto* joint = std::get_if<JointGoal>(&goals_[g]);
    if (joint == nullptr) continue;
    robot::CollisionPair pair;
    if (!checker_.inCollision(joint->configuration, &pair))
      pending_.push_back({joint->configuration, static_cast<int>(g)});
    else if (colliding_++ == 0)
      firstContact_ = pair;
  }
}

std::size_t MotionGoalSampler::collidingJointGoals(robot::CollisionPair* pair) const {
  if (pair != nullptr && colliding_ > 0) *pair = firstContact_;
  return colliding_;
}

GoalSample MotionGoalSampler::sample(const FreeSpaceDistances& knowledge,
                                     const std::function<bool()>& stop) {
  ++stats_.calls;
  for (std::size_t g = 0; g < goals_.size() && !stop(); ++g)
    if (std::holds_alternative<PoseGoal>(goals_[g])) solvePose(static_cast<int>(g));
  if (pending_.empty()) return {};
  // The candidate nearest the start's tree: the paper's C_free proximity.
  std::size_t best = 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    const double d = knowledge.toConnected(pending_[i].q);
    if (d < nearest) nearest = d, best = i;
  }
  handedOut_.push_back(std::move(pending_[best]));
  pending_.erase(pending_.begin() + static_cast<std::ptrdiff_t>(best));
  ++stats_.valid_goals;
  GoalSample out;
  out.kind = GoalKind::kGoal;
  out.configuration = handedOut_.back().q;
  out.grasp = out.configuration;
  return out;
}

void MotionGoalSampler::pathRejected(const GoalSample& goal) {
  const int g = goalOf(goal.configuration);
  if (g >= 0) pending_.push_back({goal.configuration, g});
}

int MotionGoalSampler::goalOf(const Eigen::VectorXd& q) const {
  for (const Candidate& c : handedOut_)
    if (c.q.size() == q.size() && c.q == q) return c.goal;
  return -1;
}

Eigen::Isometry3d MotionGoalSampler::drawPose(const PoseGoal& goal) {
  // Strictly inside the tolerances, so that IK's own error cannot leave them.
  constexpr double kInside = 0.999;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal;
  const auto direction = [&] {
    Eigen::Vector3d d(normal(rng_), normal(rng_), normal(rng_));
    return d.norm() > 1e-12 ? Eigen::Vector3d(d.normalized()) : Eigen::Vector3d::UnitX();
  };
  Eigen::Isometry3d pose = goal.pose;
  pose.translation() += direction() * kInside * goal.position_tolerance * std::cbrt(unit(rng_));
  pose.linear() = Eigen::AngleAxisd(kInside * goal.orientation_tolerance * unit(rng_), direction())
                      .toRotationMatrix() *
                  goal.pose.linear();
  return pose;
}

void MotionGoalSampler::solvePose(int g) {
  const auto& goal = std::get<PoseGoal>(goals_[static_cast<std::size_t>(g)]);
  const robot::RobotModel& robot = checker_.model();
  const Eigen::Isometry3d pose =
      baseInverse_ * (drawn_[static_cast<std::size_t>(g)] ? drawPose(goal) : goal.pose);
  drawn_[static_cast<std::size_t>(g)] = true;
  const bool flange = robot.linkIndex(goal.link) == robot.flangeLink();
  std::vector<Eigen::VectorXd> arms =
      flange ? ik_.solveFlange(pose, rng_) : ik_.solvePalm(pose, rng_);
  const Eigen::Index n = robot.numArmDofs();
  arms = robot::nearestWholeTurns(arms, start_.head(n), robot.lowerLimits().head(n),
                                  robot.upperLimits().head(n));
  if (arms.empty()) ++stats_.rejected.no_arm_ik;
  for (const Eigen::VectorXd& arm : arms) {
    Eigen::VectorXd q = start_;
    q.head(n) = arm;
    if (checker_.inCollision(q)) {
      ++stats_.rejected.colliding;
      continue;
    }
    pending_.push_back({std::move(q), g});
  }
}

}  // namespace hfts::planner
