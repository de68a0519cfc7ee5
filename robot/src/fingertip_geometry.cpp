#include "robot/fingertip_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hfts::robot {
namespace {

/// How deep `p` (shape frame) lies inside the shape: the distance to its
/// surface, negative outside.
double depthInside(const CollisionShape& shape, const Eigen::Vector3d& p) {
  switch (shape.type) {
    case CollisionShape::Type::kBox:
      return (0.5 * shape.size - p.cwiseAbs()).minCoeff();
    case CollisionShape::Type::kCylinder:
      return std::min(shape.size(0) - p.head<2>().norm(), 0.5 * shape.size(1) - std::abs(p.z()));
    case CollisionShape::Type::kSphere:
      return shape.size(0) - p.norm();
  }
  return -1.0;
}

/// The largest radius, in steps, whose sphere behind the pad point stays
/// inside `shape` (0: the point is not on its surface).
double radiusInside(const CollisionShape& shape, const Fingertip& tip) {
  constexpr double kStep = 1e-4, kLargest = 0.1, kTolerance = 1e-7;
  const Eigen::Isometry3d toShape = shape.origin.inverse();
  const Eigen::Vector3d point = toShape * tip.point;
  const Eigen::Vector3d normal = toShape.linear() * tip.normal.normalized();
  if (std::abs(depthInside(shape, point)) > 1e-6) return 0.0;  // not on this shape's surface
  double radius = 0.0;
  for (double r = kStep; r <= kLargest; r += kStep) {
    if (depthInside(shape, point - r * normal) < r - kTolerance) break;
    radius = r;
  }
  return radius;
}

}  // namespace

double padRadius(const RobotModel& model, const Fingertip& tip) {
  double radius = 0.0;
  for (const CollisionShape& shape : model.links().at(static_cast<std::size_t>(tip.link)).shapes)
    radius = std::max(radius, radiusInside(shape, tip));
  return radius;
}

double smallestPadRadius(const RobotModel& model) {
  double smallest = std::numeric_limits<double>::infinity();
  for (const Fingertip& tip : model.fingertips())
    smallest = std::min(smallest, padRadius(model, tip));
  return model.fingertips().empty() ? 0.0 : smallest;
}

}  // namespace hfts::robot
