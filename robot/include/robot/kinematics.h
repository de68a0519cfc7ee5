#pragma once
// Forward kinematics and Jacobians of a RobotModel (Eigen), in the robot's
// base frame.

#include <Eigen/Geometry>

#include <vector>

#include "robot/robot_model.h"

namespace hfts::robot {

/// Pose of every link (index as in RobotModel::links()) in the base frame.
using LinkPoses = std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>>;

/// Computes all link poses for configuration q (size numDofs(); not checked
/// here, validate at the boundary). `poses` is resized as needed, so a
/// caller can reuse it without allocating.
void forwardKinematics(const RobotModel& model, const Eigen::VectorXd& q, LinkPoses& poses);
LinkPoses forwardKinematics(const RobotModel& model, const Eigen::VectorXd& q);

/// Geometric Jacobian (rows: linear velocity, angular velocity) of a point
/// fixed in `link`, given in the link frame, with respect to all DoF.
/// Mimic joints add their multiplier times their column to their DoF.
Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian(const RobotModel& model, const LinkPoses& poses,
                                                  int link, const Eigen::Vector3d& point);

/// Fingertip contact points and outward pad normals in the base frame, one
/// column per fingertip of the model.
struct FingertipFrames {
  Eigen::Matrix3Xd positions;
  Eigen::Matrix3Xd normals;
};
FingertipFrames fingertipFrames(const RobotModel& model, const LinkPoses& poses);

/// A ball (base frame) that holds every fingertip's contact point at every
/// configuration within the joint limits: centred on the first moving
/// joint of the first fingertip's chain (the arm's first axis), with the
/// radius the longest chain from there, link by link (a turn keeps the
/// length of each joint's offset, a slide adds at most its range). A
/// bound, not the workspace: the arm reaches less, never more. A model
/// without fingertips gives radius 0 at the base.
struct ReachBall {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 0.0;
};
ReachBall fingertipReach(const RobotModel& model);

}  // namespace hfts::robot
