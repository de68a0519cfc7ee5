#pragma once
// How an object can rest on a flat, level support (docs/placement.md): the
// faces of its convex hull on which it stands without tipping over, and
// its pose standing on one of them. From the database's hull and centre
// of mass, so any database has them without a new preprocess step.

#include <Eigen/Geometry>

#include <vector>

#include "hfts_db/object_database.h"

namespace hfts::grasp {

/// A way the object rests: a face of its convex hull down on the support.
struct RestingFace {
  /// The face's outward normal (object frame): it points down, into the
  /// support, while the object rests on it.
  Eigen::Vector3d normal = -Eigen::Vector3d::UnitZ();
  /// The face's plane: normal . v <= offset for every point v of the hull,
  /// with equality on the face.
  double offset = 0.0;
  /// Where the object touches the support: the corners of the convex
  /// polygon of the hull's vertices within the contact tolerance of the
  /// plane (object frame, projected onto the plane), one per column, in
  /// order around it.
  Eigen::Matrix3Xd polygon;
  double area = 0.0;  ///< of the polygon (m^2)
  /// The distance (m) from the centre of mass's projection onto the plane
  /// to the polygon's nearest edge: positive inside (it stands), negative
  /// outside (it tips over).
  double margin = 0.0;
  /// Height of the centre of mass above the support (m).
  double height = 0.0;
  /// atan(margin / height): how far (rad) the object must be tilted about
  /// the polygon's nearest edge before it tips; the placements' order.
  double tipping_angle = 0.0;
  /// Turns the object so that `normal` points down (world -z): its
  /// orientation resting on this face at yaw 0.
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
};

struct PlacementOptions {
  /// Hull vertices this close (m) to a face's plane touch the support.
  double contact_tolerance = 0.0002;
  /// A face is kept when the centre of mass projects at least this far (m)
  /// inside its polygon ...
  double min_margin = 0.002;
  /// ... and the object must be tilted at least this far (rad; 10
  /// degrees) before it tips: twice the 5 degrees the rest check allows
  /// (docs/placement.md). A faceted round object has many faces it stands
  /// on only in theory.
  double min_tipping_angle = 0.174533;
};

/// The faces `object` rests on stably (margin >= options.min_margin and
/// tipping angle >= options.min_tipping_angle), the
/// largest tipping angle first; a face of the hull made of several hull
/// triangles comes once. Empty when the database has no hull or nothing
/// is stable. Deterministic. Throws InvalidArgument ("options.<field>")
/// for a negative or non-finite option.
std::vector<RestingFace> stablePlacements(const db::ObjectGeometry& object,
                                          const PlacementOptions& options = {});

/// The object's pose (object frame in the world) resting on `face` on a
/// level support whose top is at height `top`, turned by `yaw` (rad) about
/// the world's z, with its centre of mass (`centerOfMass`, object frame)
/// above `xy`.
Eigen::Isometry3d restingPose(const RestingFace& face, const Eigen::Vector3d& centerOfMass,
                              const Eigen::Vector2d& xy, double yaw, double top);

}  // namespace hfts::grasp
