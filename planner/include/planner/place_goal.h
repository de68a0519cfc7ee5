#pragma once
// Where a held object is to be put (docs/placement.md "Place goals"): a
// region on a support's level top, the object's stable ways of resting
// that the goal allows, and whether a placement there is supported. The
// search for a placement the robot reaches builds on these.

#include <Eigen/Geometry>

#include <optional>
#include <random>
#include <string>
#include <vector>

#include "grasp/stable_placements.h"
#include "hfts_db/object_database.h"
#include "robot/scene.h"

namespace hfts::planner {

/// A place goal as a request gives it.
struct PlaceGoal {
  /// The obstacle (a box whose top is level) the object goes on.
  std::string on;
  /// Where on it the object's centre of mass may stand (world x, y);
  /// unset: anywhere on the top.
  std::optional<Eigen::AlignedBox2d> area;
  /// Only ways of resting that stand the object as in its own frame: on a
  /// face whose outward normal is the object's -z (within 2 degrees).
  bool upright = false;
};

/// The top face of the support a place goal names.
struct PlaceRegion {
  std::string support;
  /// The top face's centre with z up and x, y along the box's edges.
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  Eigen::Vector2d half_extents = Eigen::Vector2d::Zero();  ///< of the top face (m)
  std::optional<Eigen::AlignedBox2d> area;                 ///< the goal's, world x, y
};

/// The region of `goal` in `scene`. Throws InvalidArgument ("place.on")
/// for an obstacle the scene does not have or that is not a box with a
/// level top, ("place.area") for an area that is empty, not finite or
/// off the top face.
PlaceRegion placeRegion(const robot::Scene& scene, const PlaceGoal& goal);

/// The ways `object` rests (grasp::stablePlacements) that `goal` allows
/// and that fit on the region's top at some yaw. Empty when there is none;
/// `why` then says why not in words ("'egg' rests stably on no face",
/// "'mug' stands upright on none of its faces", "none of the 3 ways
/// 'tray' rests fits on 'shelf_board' (top 0.30 x 0.20 m)").
std::vector<grasp::RestingFace> placeFaces(const db::ObjectDatabase& object,
                                           const PlaceRegion& region, const PlaceGoal& goal,
                                           std::string* why = nullptr);

/// Whether the object at `pose` (resting on `face`) stands on the region:
/// its contact polygon within the top face and its centre of mass
/// (`centerOfMass`, object frame) within the area.
bool supported(const PlaceRegion& region, const grasp::RestingFace& face,
               const Eigen::Vector3d& centerOfMass, const Eigen::Isometry3d& pose);

/// A placement drawn at random (a face of `faces` uniformly, the centre
/// of mass uniformly over the top face or the area, the yaw uniformly),
/// resting kRestingClearance above the top; redrawn until it is
/// supported, at most `tries` times (none then).
std::optional<Eigen::Isometry3d> samplePlacement(const PlaceRegion& region,
                                                 const std::vector<grasp::RestingFace>& faces,
                                                 const Eigen::Vector3d& centerOfMass,
                                                 std::mt19937_64& rng, int tries = 100);

}  // namespace hfts::planner
