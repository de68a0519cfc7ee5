#pragma once
// A conservative sphere model of the robot's links: the first tier of
// collision checking (spheres, then FCL; docs/collision.md). Every point of a
// link's collision geometry lies inside one of the link's spheres, and no
// point of a sphere lies farther than the model's tolerance from that
// geometry, so a configuration whose spheres touch nothing is certainly free
// and the exact check is needed only where a sphere touches something.

#include <Eigen/Core>

#include <vector>

#include "robot/robot_model.h"

namespace hfts::robot {

struct LinkSphere {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< in the link frame
  double radius = 0.0;
};

struct SphereModelOptions {
  /// Largest distance (m) from a point of a sphere to the link's geometry.
  /// Smaller means more spheres (sharp edges cost most: a sphere covers at
  /// most 2.8 tolerances of a right-angled edge); the covering is
  /// conservative either way.
  double tolerance = 0.01;
};

/// A node of a link's sphere tree: its sphere holds all of the link's
/// geometry that the leaves below it cover. Leaves have no children.
struct SphereNode {
  LinkSphere sphere;
  int left = -1;  ///< index into LinkSpheres::tree, or -1 for a leaf
  int right = -1;
  bool leaf() const { return left < 0; }
};

/// The spheres of one link (link frame) and an upper bound on how far they
/// reach beyond its geometry (max over its spheres of radius + signed
/// distance of the centre), never above the tolerance.
struct LinkSpheres {
  std::vector<LinkSphere> spheres;  ///< the leaves: together they cover the link
  /// The spheres as a binary tree (children before parents) whose root
  /// holds the whole link: a query that misses a node skips its subtree.
  std::vector<SphereNode> tree;
  int root = -1;  ///< -1 for a link without shapes
  double excess = 0.0;
};

/// One entry per link of the model (index as in RobotModel::links()); a link
/// without collision shapes has no spheres.
struct SphereModel {
  std::vector<LinkSpheres> links;

  std::size_t numSpheres() const;
  double maxExcess() const;
};

/// Signed distance (m) from `point`, in the primitive's own frame, to a box,
/// cylinder or sphere of `size` (CollisionShape::size): negative inside, exact.
double primitiveSignedDistance(CollisionShape::Type type, const Eigen::Vector3d& size,
                               const Eigen::Vector3d& point);

/// Signed distance (m) from `point` (link frame) to a collision shape:
/// negative inside. Exact for boxes, cylinders and spheres.
double signedDistance(const CollisionShape& shape, const Eigen::Vector3d& point);

/// Signed distance to the union of a link's shapes, or an upper bound on it
/// where shapes overlap (the depth inside the union is at least the depth
/// inside each shape); exact for a capsule (a cylinder with a sphere of its
/// radius on each end). +infinity for a link without shapes.
double signedDistance(const Link& link, const Eigen::Vector3d& point);

/// Covers one link. Sphere shapes are taken as they are; boxes and cylinders
/// are covered by splitting a grid of their volume (spacing tolerance / 4)
/// at the median along one of their axes until every piece's bounding sphere
/// reaches at most `tolerance` (at most half the shape's thickness) beyond
/// the link; the splits form the tree. Deterministic.
/// Throws std::invalid_argument for a tolerance that is not positive and finite.
LinkSpheres coverLink(const Link& link, const SphereModelOptions& options = {});

/// coverLink() for every link of the model. Sphere shapes are taken as they
/// are; boxes and cylinders are covered by splitting a grid of their volume
/// (spacing tolerance / 4) along its principal axis until every piece's
/// bounding sphere reaches at most `tolerance` beyond the link. Deterministic.
/// Throws std::invalid_argument for a tolerance that is not positive and finite.
SphereModel buildSphereModel(const RobotModel& model, const SphereModelOptions& options = {});

}  // namespace hfts::robot
