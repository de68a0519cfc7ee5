#pragma once
// The projection heuristic for backward trees (paper Sec. III-A.2): grasp
// configurations sit in narrow passages next to the object, so a backward
// tree step that collides near the target is bent towards a direction that
// moves the hand away from the object and opens it.

#include <Eigen/Geometry>

#include "robot/robot_model.h"

namespace hfts::planner {

class BackwardProjection {
 public:
  /// `targetCentre`: the object's centre in the world; `maxDistance`: D_m
  /// (m), the palm distance to the target below which steps are projected.
  /// The model must outlive the projection. Throws std::invalid_argument
  /// for a negative or non-finite D_m.
  BackwardProjection(const robot::RobotModel& model, const Eigen::Isometry3d& robotBase,
                     const Eigen::Vector3d& targetCentre, double maxDistance);

  double maxDistance() const { return maxDistance_; }
  void setMaxDistance(double maxDistance);

  /// Whether the palm at q is within D_m of the target centre.
  bool nearTarget(const Eigen::VectorXd& q) const;

  /// The heuristic gradient h at q (unit length): arm joint motion that
  /// moves the palm straight away from the target (damped pseudo-inverse
  /// of the palm Jacobian) plus the hand's motion towards its open posture.
  Eigen::VectorXd gradient(const Eigen::VectorXd& q) const;

  /// phi_old + <g, h> h with g = to - from; `to` itself when <g, h> <= 0
  /// (the projection never blocks an approach direction).
  Eigen::VectorXd project(const Eigen::VectorXd& from, const Eigen::VectorXd& to) const;

 private:
  const robot::RobotModel& model_;
  Eigen::Vector3d targetInBase_;
  double maxDistance_ = 0.0;
};

}  // namespace hfts::planner
