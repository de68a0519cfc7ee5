#include "robot/kinematics.h"

#include <algorithm>
#include <cmath>

#include "sin_cos.h"

namespace hfts::robot {
void forwardKinematics(const RobotModel& model, const Eigen::VectorXd& q, LinkPoses& poses) {
  const std::vector<Joint>& joints = model.joints();
  poses.resize(model.links().size());
  poses[0].setIdentity();
  // Every joint's value, and the sines and cosines of all at once.
  thread_local std::vector<double> values, sines, cosines;
  values.resize(joints.size());
  sines.resize(joints.size());
  cosines.resize(joints.size());
  for (std::size_t j = 0; j < joints.size(); ++j)
    values[j] =
        joints[j].dof < 0 ? 0.0 : joints[j].multiplier * q(joints[j].dof) + joints[j].offset;
  sinCos(values.data(), values.size(), sines.data(), cosines.data());
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const Joint& joint = joints[j];
    const Eigen::Isometry3d& parent = poses[static_cast<std::size_t>(joint.parent_link)];
    Eigen::Isometry3d& child = poses[static_cast<std::size_t>(joint.child_link)];
    Eigen::Matrix3d rotation = joint.rotation_fixed;
    Eigen::Vector3d translation = joint.origin.translation();
    if (joint.type == Joint::Type::kRevolute)
      rotation += cosines[j] * joint.rotation_cos + sines[j] * joint.rotation_sin;
    else if (joint.type == Joint::Type::kPrismatic)
      translation += values[j] * joint.slide;
    child.linear().noalias() = parent.linear() * rotation;
    child.translation().noalias() = parent.translation() + parent.linear() * translation;
    child.makeAffine();
  }
}

LinkPoses forwardKinematics(const RobotModel& model, const Eigen::VectorXd& q) {
  LinkPoses poses;
  forwardKinematics(model, q, poses);
  return poses;
}

Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian(const RobotModel& model, const LinkPoses& poses,
                                                  int link, const Eigen::Vector3d& point) {
  Eigen::Matrix<double, 6, Eigen::Dynamic> j =
      Eigen::Matrix<double, 6, Eigen::Dynamic>::Zero(6, model.numDofs());
  const Eigen::Vector3d p = poses[static_cast<std::size_t>(link)] * point;
  for (int l = link; model.links()[static_cast<std::size_t>(l)].parent_joint >= 0;) {
    const Joint& joint = model.joints()[static_cast<std::size_t>(
        model.links()[static_cast<std::size_t>(l)].parent_joint)];
    l = joint.parent_link;
    if (joint.type == Joint::Type::kFixed) continue;
    // The joint frame is the parent pose times the origin; the motion about
    // (or along) the axis does not move the axis itself.
    const Eigen::Isometry3d frame =
        poses[static_cast<std::size_t>(joint.parent_link)] * joint.origin;
    const Eigen::Vector3d axis = frame.linear() * joint.axis;
    if (joint.type == Joint::Type::kRevolute) {
      j.col(joint.dof).head<3>() += joint.multiplier * axis.cross(p - frame.translation());
      j.col(joint.dof).tail<3>() += joint.multiplier * axis;
    } else {
      j.col(joint.dof).head<3>() += joint.multiplier * axis;
    }
  }
  return j;
}

FingertipFrames fingertipFrames(const RobotModel& model, const LinkPoses& poses) {
  const std::vector<Fingertip>& tips = model.fingertips();
  FingertipFrames out{Eigen::Matrix3Xd(3, tips.size()), Eigen::Matrix3Xd(3, tips.size())};
  for (std::size_t i = 0; i < tips.size(); ++i) {
    const Eigen::Isometry3d& pose = poses[static_cast<std::size_t>(tips[i].link)];
    out.positions.col(static_cast<Eigen::Index>(i)) = pose * tips[i].point;
    out.normals.col(static_cast<Eigen::Index>(i)) = pose.linear() * tips[i].normal;
  }
  return out;
}

ReachBall fingertipReach(const RobotModel& model) {
  const std::vector<Joint>& joints = model.joints();
  const LinkPoses home = forwardKinematics(model, model.home());
  // The largest |value| a joint takes within its DoF's limits.
  const auto largestValue = [&](const Joint& joint) {
    const auto dof = static_cast<Eigen::Index>(joint.dof);
    return std::max(std::abs(joint.multiplier * model.lowerLimits()(dof) + joint.offset),
                    std::abs(joint.multiplier * model.upperLimits()(dof) + joint.offset));
  };
  ReachBall ball;
  bool centred = false;
  for (const Fingertip& tip : model.fingertips()) {
    // From the fingertip's link up to the first moving joint: the lengths
    // below it, and where it is (every joint above it is fixed).
    double length = tip.point.norm();
    Eigen::Vector3d anchor = home[static_cast<std::size_t>(tip.link)].translation();
    for (int l = tip.link; model.links()[static_cast<std::size_t>(l)].parent_joint >= 0;) {
      const Joint& joint =
          joints[static_cast<std::size_t>(model.links()[static_cast<std::size_t>(l)].parent_joint)];
      l = joint.parent_link;
      if (joint.type == Joint::Type::kPrismatic) length += largestValue(joint) * joint.slide.norm();
      bool movesAbove = false;
      for (int k = l; model.links()[static_cast<std::size_t>(k)].parent_joint >= 0;) {
        const Joint& above = joints[static_cast<std::size_t>(
            model.links()[static_cast<std::size_t>(k)].parent_joint)];
        movesAbove = movesAbove || above.type != Joint::Type::kFixed;
        k = above.parent_link;
      }
      if (joint.type != Joint::Type::kFixed && !movesAbove) {
        // The first moving joint: its frame's origin stays where it is.
        anchor = (home[static_cast<std::size_t>(joint.parent_link)] * joint.origin).translation();
        break;
      }
      length += joint.origin.translation().norm();
    }
    if (!centred) {
      ball.centre = anchor;
      centred = true;
    }
    ball.radius = std::max(ball.radius, (anchor - ball.centre).norm() + length);
  }
  return ball;
}

}  // namespace hfts::robot
