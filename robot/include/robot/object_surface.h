#pragma once
// The target object's exact surface: signed distances of points and of the
// robot's collision primitives to its mesh, with the mesh's own normals.
// What decides whether a fingertip touches the object, how deep a link is
// inside it, and where a grasp's actual contacts are (grasp/hand_closing.h).

#include <Eigen/Geometry>

#include <limits>
#include <memory>
#include <unordered_map>
#include <vector>

#include "hfts_db/object_database.h"
#include "hfts_db/triangle_bvh.h"
#include "robot/robot_model.h"

namespace hfts::robot {

/// The point of the surface nearest to a query point.
struct SurfacePoint {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< object frame
  /// Outward unit normal of the mesh there: the triangle's inside a face,
  /// the angle-weighted pseudo-normal on an edge or at a vertex (Baerentzen
  /// and Aanaes 2005), which also signs the distance.
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  /// Of the query point: > 0 outside the solid, < 0 inside (m).
  double signed_distance = 0.0;
};

/// The smallest signed distance over a primitive's solid, and where.
struct ShapeDistance {
  /// Never above the true minimum of the signed distance over the shape,
  /// and within the requested tolerance of it: > 0 is a clearance, < 0 a
  /// depth inside the object (the deepest point of the shape).
  double lower = 0.0;
  /// The point of the shape (object frame) where the smallest signed
  /// distance was evaluated, and the surface point nearest to it.
  Eigen::Vector3d shape_point = Eigen::Vector3d::Zero();
  SurfacePoint surface;
};

/// How far a link is from the surface (ObjectSurface::linkClearance).
struct Clearance {
  double distance = 0.0;  ///< m; 0 when a shape touches or crosses a triangle
  /// The nearest points of the link and of the surface (object frame):
  /// set when distance > 0.
  Eigen::Vector3d on_link = Eigen::Vector3d::Zero();
  Eigen::Vector3d on_surface = Eigen::Vector3d::Zero();
};

/// An object's mesh with what signed-distance queries need: Embree's BVH
/// (exact double-precision closest points) and the pseudo-normals of edges
/// and vertices. Read-only after construction: any number of threads may
/// query one surface.
///
/// Signs are exact for points outside the solid and inside one closed,
/// consistently wound component; where two closed components overlap (a
/// handle sunk into a wall) a point inside both may be reported outside
/// the one whose buried face is nearest. Open meshes have no inside: the
/// sign then follows the winding of the nearest face.
class ObjectSurface {
 public:
  /// Throws hfts::InvalidArgument ("geometry") for a geometry without
  /// triangles or with an index out of range.
  explicit ObjectSurface(const db::ObjectGeometry& geometry);
  ~ObjectSurface();
  ObjectSurface(const ObjectSurface&) = delete;
  ObjectSurface& operator=(const ObjectSurface&) = delete;

  /// The surface point nearest to p (object frame) and p's signed distance.
  SurfacePoint nearest(const Eigen::Vector3d& p) const;

  /// The smallest signed distance over the solid of `shape` placed at
  /// `pose` (the shape's frame in the object frame; the shape's own
  /// `origin` is not applied), by branch and bound on the 1-Lipschitz
  /// signed distance: cells of the shape are split until the smallest
  /// lower bound is within `tolerance` (m, > 0) of the smallest value
  /// found. The search also stops once the answer is known to be above
  /// `stopAbove` (it then returns a lower bound above it, not the minimum)
  /// or known to be below `stopBelow` (it then returns a value below it,
  /// found at `shape_point`): callers that only ask "closer than x?" pass
  /// x as both. The object's distance
  /// grid, when it has one, bounds cells before any exact query: a shape
  /// far from the object costs a few grid look-ups. `shape_point` and
  /// `surface` are then those of the last exact query (none: the shape's
  /// centre and a default point).
  ShapeDistance shapeDistance(const CollisionShape& shape, const Eigen::Isometry3d& pose,
                              double tolerance,
                              double stopAbove = std::numeric_limits<double>::infinity(),
                              double stopBelow = -std::numeric_limits<double>::infinity()) const;

  /// shapeDistance over every shape of `link` (each at `linkPose` times its
  /// origin, object frame): the smallest. A link without shapes gives an
  /// infinite distance.
  /// A lower bound of the signed distance at p (object frame) from the
  /// object's signed distance grid (DistanceGrid::lowerBound), within
  /// about 1.7 grid spacings of it; -infinity without a signed grid.
  double gridBound(const Eigen::Vector3d& p) const;

  ShapeDistance linkDistance(const Link& link, const Eigen::Isometry3d& linkPose, double tolerance,
                             double stopAbove = std::numeric_limits<double>::infinity(),
                             double stopBelow = -std::numeric_limits<double>::infinity()) const;

  /// The exact distance (m) between the shapes of `link` (at `linkPose`,
  /// object frame) and the mesh's triangles, from FCL (its BVH culls, GJK
  /// decides per triangle): fast where shapeDistance would refine a long
  /// line of contact. 0 when a shape touches or crosses a triangle. It
  /// measures to the surface, not into the solid: a link wholly inside
  /// the object has a positive clearance (shapeDistance tells).
  Clearance linkClearance(const Link& link, const Eigen::Isometry3d& linkPose) const;

  /// How deep (m, >= 0) the link reaches into the solid: 0 when it is
  /// apart from the surface and outside, else -linkDistance() to
  /// `tolerance` (an upper bound of the true depth).
  double linkDepth(const Link& link, const Eigen::Isometry3d& linkPose, double tolerance) const;

 private:
  Eigen::Vector3d pseudoNormal(std::uint32_t triangle, const Eigen::Vector3d& point) const;

  db::Points3 vertices_;
  db::Faces3 triangles_;
  db::DistanceGrid grid_;  // signed when the object is closed, else unsigned
  struct Fcl;              // the mesh as an FCL collision object
  std::unique_ptr<const Fcl> fcl_;
  std::unique_ptr<db::TriangleBvh> bvh_;
  std::vector<Eigen::Vector3d> faceNormals_;                        // unit, per triangle
  std::vector<Eigen::Vector3d> vertexNormals_;                      // angle-weighted, unit
  std::unordered_map<std::uint64_t, Eigen::Vector3d> edgeNormals_;  // key: smaller, larger vertex
};

}  // namespace hfts::robot
