#pragma once
// The goal sampler of motion-only goals (motion_goal.h), internal to the
// planner library: joint goals handed out once each, pose goals turned into
// arm configurations by IK at poses drawn within their tolerances, the free
// one nearest the start's tree first (the paper's C_free proximity, without
// a hierarchy).

#include <Eigen/Geometry>

#include <random>
#include <vector>

#include "planner/goal_sampler.h"
#include "planner/motion_goal.h"
#include "robot/arm_ik.h"
#include "robot/collision_checker.h"

namespace hfts::planner {

class MotionGoalSampler final : public GoalSampler {
 public:
  /// `goals` checked (checkGoals); the robot's base at `base`; the hand of
  /// pose goals at `start`'s posture. Everything must outlive the sampler.
  MotionGoalSampler(const robot::ArmIk& ik, robot::CollisionChecker& checker, std::mt19937_64& rng,
                    const Eigen::Isometry3d& base, std::vector<MotionGoal> goals,
                    Eigen::VectorXd start);

  /// One free goal configuration not handed out before, or kNone: each
  /// joint goal once (a colliding one never), and for each pose goal one
  /// IK solve per call at a pose drawn within its tolerances (the first at
  /// the pose itself).
  GoalSample sample(const FreeSpaceDistances& knowledge,
                    const std::function<bool()>& stop) override;

  /// A goal whose path failed the final check waits to be handed out
  /// again: a new tree may reach it by another path (a joint goal is the
  /// only one of its kind).
  void pathRejected(const GoalSample& goal) override;

  /// The goal a configuration handed out satisfies (index into the goals),
  /// -1 when it was not handed out.
  int goalOf(const Eigen::VectorXd& q) const;

  /// Joint goals that collide; with `pair` (when given) the first's contact.
  std::size_t collidingJointGoals(robot::CollisionPair* pair = nullptr) const;

 private:
  struct Candidate {
    Eigen::VectorXd q;
    int goal = 0;
  };
  /// IK of pose goal `g` at a pose drawn within its tolerances; the free
  /// solutions join `pending_`.
  void solvePose(int g);
  Eigen::Isometry3d drawPose(const PoseGoal& goal);

  const robot::ArmIk& ik_;
  robot::CollisionChecker& checker_;
  std::mt19937_64& rng_;
  Eigen::Isometry3d baseInverse_;
  std::vector<MotionGoal> goals_;
  Eigen::VectorXd start_;
  std::vector<bool> drawn_;  // a pose goal solved at its pose once
  std::vector<Candidate> pending_;
  std::vector<Candidate> handedOut_;
  std::size_t colliding_ = 0;
  robot::CollisionPair firstContact_;
};

}  // namespace hfts::planner
