#include "robot/motion_bound.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hfts::robot {
namespace {

/// The largest distance (m) from a link's frame origin to a point of its
/// collision shapes and its mesh (a held body's); 0 for a link without
/// either.
double linkReach(const Link& link) {
  double reach = 0.0;
  if (link.mesh != nullptr) reach = link.mesh->vertices.rowwise().norm().maxCoeff();
  for (const CollisionShape& shape : link.shapes) {
    // A sphere's points lie within its radius of its centre; a box's or a
    // cylinder's within the half diagonal of its bounding box.
    const double extent =
        shape.type == CollisionShape::Type::kSphere ? shape.size.x() : halfExtents(shape).norm();
    reach = std::max(reach, shape.origin.translation().norm() + extent);
  }
  return reach;
}

/// The largest |value| joint `joint` takes over the limits of its DoF.
double largestValue(const RobotModel& model, const Joint& joint) {
  const auto d = static_cast<Eigen::Index>(joint.dof);
  return std::max(std::abs(joint.multiplier * model.lowerLimits()(d) + joint.offset),
                  std::abs(joint.multiplier * model.upperLimits()(d) + joint.offset));
}

}  // namespace

MotionBound::MotionBound(const RobotModel& model)
    : coefficients_(
          Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(model.links().size()), model.numDofs())),
      chains_(model.links().size()) {
  for (std::size_t l = 0; l < model.links().size(); ++l) {
    const Link& link = model.links()[l];
    if (link.shapes.empty() && link.mesh == nullptr) continue;
    // reach: a bound on the distance from the child frame origin of the
    // current joint (a point on its axis) to any point of the link.
    double reach = linkReach(link);
    for (int j = link.parent_joint; j >= 0;) {
      const Joint& joint = model.joints()[static_cast<std::size_t>(j)];
      if (joint.dof >= 0 && joint.type != Joint::Type::kFixed) {
        const double perUnit = joint.type == Joint::Type::kRevolute ? reach : joint.slide.norm();
        const double coefficient = std::abs(joint.multiplier) * perUnit;
        coefficients_(static_cast<Eigen::Index>(l), joint.dof) += coefficient;
        chains_[l].push_back({j, joint.dof, coefficient});
      } else {
        chains_[l].push_back({j, -1, 0.0});  // on the chain all the same: marks the ancestors
      }
      // The child frame's origin in the parent link's frame lies at the
      // joint's origin, moved along the slide for a prismatic joint.
      reach += joint.origin.translation().norm();
      if (joint.type == Joint::Type::kPrismatic && joint.dof >= 0)
        reach += largestValue(model, joint) * joint.slide.norm();
      j = model.links()[static_cast<std::size_t>(joint.parent_link)].parent_joint;
    }
  }
}

void MotionBound::check(int link, const Eigen::VectorXd& step) const {
  if (link < 0 || link >= coefficients_.rows())
    throw std::invalid_argument("MotionBound: no link " + std::to_string(link) +
                                " (the robot has " + std::to_string(coefficients_.rows()) + ")");
  if (step.size() != coefficients_.cols())
    throw std::invalid_argument("MotionBound: a step of " + std::to_string(step.size()) +
                                " values for " + std::to_string(coefficients_.cols()) + " DoFs");
}

double MotionBound::link(int link, const Eigen::VectorXd& step) const {
  check(link, step);
  return coefficients_.row(link).dot(step.cwiseAbs());
}

double MotionBound::pair(int a, int b, const Eigen::VectorXd& step) const {
  check(a, step);
  check(b, step);
  const std::vector<ChainJoint>& chainA = chains_[static_cast<std::size_t>(a)];
  const std::vector<ChainJoint>& chainB = chains_[static_cast<std::size_t>(b)];
  auto on = [](const std::vector<ChainJoint>& chain, int joint) {
    return std::any_of(chain.begin(), chain.end(),
                       [joint](const ChainJoint& c) { return c.joint == joint; });
  };
  // A joint on both chains lies above the common ancestor.
  double travel = 0.0;
  for (const ChainJoint& c : chainA)
    if (c.dof >= 0 && !on(chainB, c.joint)) travel += c.coefficient * std::abs(step(c.dof));
  for (const ChainJoint& c : chainB)
    if (c.dof >= 0 && !on(chainA, c.joint)) travel += c.coefficient * std::abs(step(c.dof));
  return travel;
}

}  // namespace hfts::robot
