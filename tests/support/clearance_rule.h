#pragma once
// The clearance rule (robot::CollisionScene) measured independently of the
// checker that applies it: FCL distances of every pair the rule holds to
// the clearance, which links count as static or rigid found by forward
// kinematics, not by the checker's joint chains.

#include <Eigen/Geometry>

#include <algorithm>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "robot/collision_checker.h"
#include "robot/kinematics.h"

namespace hfts::test {

/// The smallest distance at q between two things the clearance rule keeps
/// apart, and what they are.
struct RuleDistance {
  double distance = std::numeric_limits<double>::infinity();
  std::string what;
};

/// Which links and link pairs the clearance rule holds to the clearance,
/// found by moving every DoF: a link whose pose does not change is
/// static, two links whose relative pose does not change are rigid.
class ClearanceRule {
 public:
  /// `handFromTarget`: the hand's links are held to the clearance from the
  /// target too, as a certified transit holds them
  /// (robot::CertifyRule::kTransit), where a scene's rule lets them near.
  explicit ClearanceRule(const robot::RobotModel& model, bool handFromTarget = false)
      : model_(model), handFromTarget_(handFromTarget) {
    const Eigen::VectorXd a = model.home();
    const Eigen::VectorXd b = a + Eigen::VectorXd::Constant(a.size(), 0.37);
    const robot::LinkPoses pa = robot::forwardKinematics(model, a);
    const robot::LinkPoses pb = robot::forwardKinematics(model, b);
    const auto same = [](const Eigen::Isometry3d& x, const Eigen::Isometry3d& y) {
      return (x.matrix() - y.matrix()).cwiseAbs().maxCoeff() < 1e-9;
    };
    const std::size_t links = model.links().size();
    for (std::size_t l = 0; l < links; ++l) {
      if (model.links()[l].shapes.empty()) continue;
      const bool still = same(pa[l], pb[l]);
      if (!still) moving_.push_back(static_cast<int>(l));
      for (std::size_t k = l + 1; k < links; ++k) {
        if (model.links()[k].shapes.empty()) continue;
        if (model.isCollisionDisabled(static_cast<int>(l), static_cast<int>(k))) continue;
        const bool hands =
            model.isHandLink(static_cast<int>(l)) && model.isHandLink(static_cast<int>(k));
        if (hands || same(pa[l].inverse() * pa[k], pb[l].inverse() * pb[k]) ||
            jointsApart(l, k) <= robot::kClearanceJointsApart)
          continue;
        pairs_.emplace_back(static_cast<int>(l), static_cast<int>(k));
      }
    }
  }

  /// The smallest distance at q that the rule holds to the clearance: every
  /// moving link to the obstacles (not the hand's under the grasp rule or
  /// when `handFree`), every moving link but the hand's to the target,
  /// every pair of links that may collide, move apart, are not both the
  /// hand's and have more than robot::kClearanceJointsApart moving joints
  /// between them.
  /// Distances beyond `exactWithin` (m; 0: all exact) may be lower bounds
  /// (robot::CollisionChecker::linkClearances).
  RuleDistance at(robot::CollisionChecker& checker, const Eigen::VectorXd& q,
                  bool graspRule = false, bool handFree = false, double exactWithin = 0.0) const {
    RuleDistance out;
    std::vector<int> obstacles, target;
    for (const int link : moving_) {
      const bool hand = model_.isHandLink(link);
      if (!hand || (!graspRule && !handFree)) obstacles.push_back(link);
      if (!hand || handFromTarget_) target.push_back(link);
    }
    std::vector<double> d;
    const auto keep = [&](double distance, const std::string& what) {
      if (distance < out.distance) out = {distance, what};
    };
    checker.linkClearances(q, obstacles, d, robot::CollisionRequest::obstaclesOnly(), exactWithin);
    for (std::size_t i = 0; i < d.size(); ++i)
      keep(d[i], model_.links()[static_cast<std::size_t>(obstacles[i])].name + " / obstacles");
    checker.linkClearances(q, target, d, robot::CollisionRequest::targetOnly(), exactWithin);
    for (std::size_t i = 0; i < d.size(); ++i)
      keep(d[i], model_.links()[static_cast<std::size_t>(target[i])].name + " / target");
    checker.pairClearances(q, pairs_, d);
    for (std::size_t i = 0; i < d.size(); ++i)
      keep(d[i], model_.links()[static_cast<std::size_t>(pairs_[i].first)].name + " / " +
                     model_.links()[static_cast<std::size_t>(pairs_[i].second)].name);
    return out;
  }

 private:
  /// The moving joints between two links, from the joints' own parent and
  /// child links: those above one link and not above the other.
  int jointsApart(std::size_t a, std::size_t b) const {
    const auto above = [this](std::size_t link) {
      std::set<std::size_t> joints;
      for (bool found = true; found;) {
        found = false;
        for (std::size_t j = 0; j < model_.joints().size(); ++j) {
          const robot::Joint& joint = model_.joints()[j];
          if (static_cast<std::size_t>(joint.child_link) != link) continue;
          if (joint.type != robot::Joint::Type::kFixed) joints.insert(j);
          link = static_cast<std::size_t>(joint.parent_link);
          found = true;
          break;
        }
      }
      return joints;
    };
    const std::set<std::size_t> ja = above(a), jb = above(b);
    int apart = 0;
    for (const std::size_t j : ja) apart += jb.count(j) == 0 ? 1 : 0;
    for (const std::size_t j : jb) apart += ja.count(j) == 0 ? 1 : 0;
    return apart;
  }

  const robot::RobotModel& model_;
  bool handFromTarget_;
  std::vector<int> moving_;
  std::vector<std::pair<int, int>> pairs_;
};

}  // namespace hfts::test
