#pragma once
// An object seen from one side only: a segmented point cloud from a depth
// camera. What lies behind the observed surface is unknown, so the
// object's collision shape is a conservative stand-in for it
// (docs/point_clouds.md#objects-from-a-partial-view).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hfts_db/triangle_mesh.h"
#include "preprocess/convex_hull.h"

namespace hfts::preprocess {

/// How far inside the solid built from views an observed point may lie
/// and still be a contact (m): about the noise left after smoothing.
/// Deeper points (the inside of a mug seen from above, any pocket the
/// convex solid fills) are where no finger closing on the solid can touch.
inline constexpr double kMaxViewContactDepth = 0.003;

/// How far above the floor a corner of the solid built from views is put
/// down on it too (buildObjectDatabaseFromViews): the object's foot, which
/// the views see least.
inline constexpr double kFootHeight = 0.01;

struct ViewOptions {
  /// The camera's centre in the cloud's frame (whose z is up: the frame of
  /// the world the object stands in).
  Eigen::Vector3d viewpoint = Eigen::Vector3d::Zero();
  /// How far behind each observed point (along the camera's ray) the
  /// object may reach; 0: the largest edge of the points' bounding box
  /// (the object is assumed no deeper than it is wide or tall).
  double hidden_depth = 0.0;
  /// The height below which the object does not reach (the top of its
  /// support); unset: the lowest observed point.
  std::optional<double> floor;
  /// Radius (m) of the moving-least-squares smoothing of the sensor's
  /// noise before anything else (smoothView); 0: none.
  double smoothing = 0.01;
};

/// A view with its noise smoothed away: PCL's moving least squares (a
/// quadratic fitted over `radius` around each point, the point projected
/// onto it), the fitted surface's normals turned towards `viewpoint`, and
/// for each point kept the index of the input point it came from (points
/// with too few neighbours for a fit are dropped). Throws
/// hfts::InvalidArgument ("smoothing") for a radius that is not positive.
struct SmoothedView {
  Vertices points;
  Vertices normals;
  std::vector<std::uint32_t> source;
};
SmoothedView smoothView(const Vertices& points, const Eigen::Vector3d& viewpoint, double radius);

/// Throws hfts::InvalidArgument ("points") for fewer than 4 points or
/// non-finite ones.
void checkViewPoints(const Vertices& points);

/// The points whose convex hull is the object's conservative shape: every
/// observed point and the end of its shadow, the ray from the camera
/// through the point continued `hidden_depth` beyond it and cut at the
/// floor. Every point of the object the camera could not see lies on such
/// a shadow (if the segmentation holds all of the object's pixels and the
/// object is no deeper than hidden_depth), so the hull holds the object.
struct HiddenSide {
  Vertices corners;
  double hidden_depth = 0.0;  ///< resolved
  double floor = 0.0;         ///< resolved
};

/// Throws hfts::InvalidArgument ("points" for fewer than 4 points or
/// non-finite ones, "viewpoint" for a non-finite one or one on a point,
/// "hidden_depth" for a negative or non-finite one, "floor" for a
/// non-finite one or one above every point).
HiddenSide hiddenSide(const Vertices& points, const ViewOptions& options);

/// The corners of the solid two convex solids have in common (each
/// conservative, so is their intersection): the corners of each inside the
/// other and where the edges of each cross the faces of the other. Empty
/// when they do not overlap.
Vertices intersectionCorners(const ConvexHull& a, const ConvexHull& b);

/// The whole depth image a view's points came from: where the camera saw
/// through, and so where the object is not. With it the builder carves
/// (carveViews) instead of trusting the points' shadows alone, which miss
/// what another object hid and what lies below the lowest observed point.
struct DepthEvidence {
  /// The optical frame (x right, y down, z along the view) in the world.
  Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();
  double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;  ///< pinhole (pixels)
  int width = 0;
  int height = 0;
  /// Depths (m, along the optical axis), row-major; 0 or NaN: no reading.
  std::vector<float> depths;
  /// 1 where the pixel sees the object (the segmentation), as depths.
  std::vector<std::uint8_t> target;
};

/// One segmented view of the object: its points (metres, z up), the
/// sensor's normals if it gave them (one per point, either sign), how it
/// was seen and, when known, the whole image it came from.
struct SensedView {
  Vertices points;
  std::optional<Vertices> normals;
  ViewOptions options;
  std::optional<DepthEvidence> depth = std::nullopt;
};

/// The depth noise (m) a reading of another surface may hide the object
/// behind: a point up to this much nearer than a non-object pixel's depth
/// is not seen free.
inline constexpr double kCarvingMargin = 0.005;

/// Where the object may be, given the depth images (carveViews).
struct Carving {
  /// Centres of the voxels no camera saw free that connect to the
  /// object's observed points (26-neighbours).
  Vertices centres;
  /// Edge (m); voxel (i, j, k) spans [i, i + 1) edges along each axis.
  double voxel = 0.0;
  double floor = 0.0;         ///< the support's height: nothing of the object lies below it
  bool floor_fitted = false;  ///< floor from a horizontal plane the cameras saw
  double reach = 0.0;         ///< how far beyond its observed points the object may extend
  /// Per view, the pixels of the object's outline, and those of them next
  /// to a nearer surface, an unseen pixel or the image's border: where
  /// another object (or the frame) hides part of it.
  std::vector<std::size_t> outline, occluded;
};

/// A view whose object outline is hidden along more than this share of
/// its pixels may hide much of the object: its observed extent bounds
/// nothing, and without a given --hidden-depth the carving reaches
/// kOccludedReach beyond the points.
inline constexpr double kOccludedOutline = 0.05;
/// What the carving assumes of an object some view hides (m): no part of
/// it lies farther than this beyond its observed points (household
/// objects; a larger one needs --hidden-depth).
inline constexpr double kOccludedReach = 0.3;

/// Space carving around `points` (the object's observed points, world)
/// within `reach` of their box, above `floor` (unset: the highest
/// horizontal plane the cameras saw at or below the lowest observed
/// point, fitted by PCL's RANSAC among the other pixels; none found: that
/// point). A voxel centre is seen free by a camera when its pixel's reading
/// lies behind it: beyond it for an object pixel, more than kCarvingMargin
/// beyond it for another surface, or anywhere on the support for a pixel
/// whose ray comes down on the support (the object stands on it). Pixels
/// without a reading take the nearest reading within two pixels; where
/// there is none, and outside the image, nothing is seen free. The voxel's
/// edge is 3 mm, or larger so that the block holds at most 8e6 of them.
/// Throws hfts::InvalidArgument ("depth" for an image whose size, camera
/// or mask is inconsistent; "reach", "floor").
Carving carveViews(const std::vector<DepthEvidence>& views, const Vertices& points, double reach,
                   std::optional<double> floor);

/// Axis-aligned boxes (lowest and highest corner) that together are the
/// cubes of edge `voxel` centred on `centres` (centres on one grid of that
/// spacing), neighbours merged greedily: along x, then y, then z.
std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> mergedVoxels(const Vertices& centres,
                                                                      double voxel);

/// Indices of one point per occupied cube of edge `voxel` (the first in
/// the input's order, so a point keeps its own normal), in input order.
std::vector<std::uint32_t> onePerVoxel(const Vertices& points, double voxel);

}  // namespace hfts::preprocess
