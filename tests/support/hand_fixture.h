#pragma once
// The bundled hand's reachability, for grasp tests that need no planner.

#include <random>

#include "grasp/hand_map_builder.h"
#include "grasp/hand_reachability.h"
#include "robot/kinematics.h"
#include "robot_fixture.h"

namespace hfts::test {

/// R(h) of the KR5 + SDH from a freshly built hand map (default query
/// options), built once per test program.
inline const grasp::HandReachability& kr5SdhReachability() {
  static const grasp::HandReachability r(kr5Sdh(), grasp::buildHandMap(kr5Sdh()));
  return r;
}

/// A hand configuration with its fingertips and pad normals in the palm
/// frame, by the model's own forward kinematics (not the map's hand chains).
struct HandPosture {
  Eigen::VectorXd hand;
  Eigen::Matrix3Xd tips;
  Eigen::Matrix3Xd pads;
};

inline HandPosture handPostureOf(const robot::RobotModel& model, const Eigen::VectorXd& hand) {
  Eigen::VectorXd q = model.home();
  q.tail(model.numHandDofs()) = hand;
  const robot::LinkPoses poses = robot::forwardKinematics(model, q);
  const robot::FingertipFrames frames = robot::fingertipFrames(model, poses);
  const Eigen::Isometry3d palmInverse = poses[static_cast<std::size_t>(model.palmLink())].inverse();
  return {hand, palmInverse * frames.positions, palmInverse.linear() * frames.normals};
}

/// A uniformly drawn hand configuration that passes the grasp-posture test.
inline HandPosture randomGraspPosture(const robot::RobotModel& model, std::mt19937_64& rng) {
  const int arm = model.numArmDofs();
  for (;;) {
    Eigen::VectorXd hand(model.numHandDofs());
    for (Eigen::Index d = 0; d < hand.size(); ++d)
      hand(d) = std::uniform_real_distribution<double>(model.lowerLimits()(arm + d),
                                                       model.upperLimits()(arm + d))(rng);
    HandPosture p = handPostureOf(model, hand);
    if (grasp::isGraspPosture(p.tips, p.pads, grasp::HandMapOptions{})) return p;
  }
}

/// A random rigid motion: uniform rotation, translation of about a metre.
inline Eigen::Isometry3d randomPose(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() =
      Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng)).normalized().matrix();
  pose.translation() = Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
  return pose;
}

}  // namespace hfts::test
