#pragma once
// An object seen from one side only: a segmented point cloud from a depth
// camera. What lies behind the observed surface is unknown, so the
// object's collision shape is a conservative stand-in for it
// (docs/point_clouds.md#objects-from-a-partial-view).

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "hfts_db/triangle_mesh.h"
#include "preprocess/convex_hull.h"

namespace hfts::preprocess {

/// How far inside the solid built from views an observed point may lie
/// and still be a contact (m): about the noise left after smoothing.
/// Deeper points (the inside of a mug seen from above, any pocket the
/// convex solid fills) are where no finger closing on the solid can touch.
inline constexpr double kMaxViewContactDepth = 0.003;

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

/// One segmented view of the object: its points (metres, z up), the
/// sensor's normals if it gave them (one per point, either sign), and how
/// it was seen.
struct SensedView {
  Vertices points;
  std::optional<Vertices> normals;
  ViewOptions options;
};

/// Indices of one point per occupied cube of edge `voxel` (the first in
/// the input's order, so a point keeps its own normal), in input order.
std::vector<std::uint32_t> onePerVoxel(const Vertices& points, double voxel);

}  // namespace hfts::preprocess
