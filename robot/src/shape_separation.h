// Separating-axis proofs for pairs of primitive shapes: a cheap way to
// know, before FCL's narrowphase, that a box, cylinder or sphere pair is
// apart.
#pragma once

#include <Eigen/Geometry>

namespace hfts::robot {

/// A box, cylinder or sphere where it stands. `type` is a
/// CollisionShape::Type value (0 box, 1 cylinder, 2 sphere); `size` as in
/// CollisionShape (box edges; cylinder radius and length along local z;
/// sphere radius).
struct PlacedShape {
  int type = 2;
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
};

/// max over the shape's points x of n . x, for any direction n (not
/// necessarily unit): the shape's support function, exact.
double support(const PlacedShape& shape, const Eigen::Vector3d& n);

/// True when some direction proves the two shapes more than `gap` apart:
/// support(a, n) + gap * |n| < -support(b, -n). With a sphere, the
/// direction from the other shape's point nearest to its centre (every
/// pair apart is proven). Otherwise the direction between the shapes'
/// nearest core points (the cylinder's axis, the box's longest middle
/// segment), the centre line, the faces and axes of both shapes, and, for
/// two boxes, the nine edge-pair directions (with the faces, every
/// separating axis two boxes can have). False means "not proven apart",
/// never "touching": such pairs go to FCL.
bool provablyApart(const PlacedShape& a, const PlacedShape& b, double gap);

/// The nearest points of segments [p0, p1] and [q0, q1] (either may be a
/// point); returns the squared distance, writes the points.
double closestPointsOfSegments(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                               const Eigen::Vector3d& q0, const Eigen::Vector3d& q1,
                               Eigen::Vector3d& onP, Eigen::Vector3d& onQ);

}  // namespace hfts::robot
