#pragma once
// Obstacles a sensor sees: point clouds (PCD or PLY files, or points given
// inline) and depth images, turned into collision geometry both tiers of
// the checker use (docs/point_clouds.md). The cloud's obstacle is the union
// of the voxels (axis-aligned cubes of edge `voxel` in the obstacle's
// frame, voxel (i, j, k) spanning [i v, (i + 1) v) along each axis) that
// come within `radius` of a point: FCL checks it as an octree (octomap),
// the sphere tier by a grid of distances to it.

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "hfts_db/distance_grid.h"
#include "hfts_db/triangle_mesh.h"

namespace hfts::robot {

/// How points become an obstacle.
struct CloudOptions {
  /// Voxel edge (m): the resolution of the obstacle.
  double voxel = 0.01;
  /// The sensor's noise (m): every voxel within this distance of a point
  /// is occupied, so the obstacle holds a ball of this radius around each.
  double radius = 0.005;
  /// What the sensor cannot see behind what it saw: from a known
  /// `viewpoint` (obstacle frame; a depth image's camera), each point's ray
  /// is occupied for `shadow` metres beyond the point as well, so that the
  /// back of an obstacle seen from one side is an obstacle too (0: the
  /// points only). Without a viewpoint there are no shadows.
  double shadow = 0.2;
  std::optional<Eigen::Vector3d> viewpoint;
  /// PCL's statistical outlier removal (a point whose mean distance to its
  /// `outlier_neighbours` nearest is more than `outlier_stddev` standard
  /// deviations above the cloud's mean is dropped). Off by default: it
  /// can remove a thin real obstacle; a depth camera's flying pixels are
  /// its use.
  bool remove_outliers = false;
  int outlier_neighbours = 8;
  double outlier_stddev = 2.0;
};

/// A pinhole depth camera (the optical frame: x right, y down, z along
/// the view), and which depths count as seen.
struct DepthCamera {
  double fx = 0.0, fy = 0.0;  ///< focal lengths (pixels)
  double cx = 0.0, cy = 0.0;  ///< principal point (pixels)
  double min_depth = 0.05;    ///< m: nearer readings are dropped (invalid)
  double max_depth = 3.0;     ///< m: farther readings are dropped (background)
};

/// A depth image: depths in metres, row-major (width columns), NaN or 0
/// where the camera saw nothing.
struct DepthImage {
  int width = 0;
  int height = 0;
  std::vector<float> depths;
};

/// The occupied voxels of a cloud, and what the checker's tiers read.
struct VoxelCloud {
  CloudOptions options;
  /// The points after filtering (obstacle frame), one per row.
  Vertices points;
  /// The block of voxels that holds every occupied one: its first voxel's
  /// index and its size.
  std::array<int, 3> first{0, 0, 0};
  std::array<int, 3> dims{0, 0, 0};
  /// 1 where occupied, index x + dims[0] * (y + dims[1] * z) in the block.
  std::vector<std::uint8_t> occupied;
  std::size_t occupied_count = 0;
  /// Distances (lower bounds, rounded down to float) from the occupied
  /// voxels at the centres of the block's voxels and one voxel around it:
  /// the sphere tier's grid (unsigned: 0 inside).
  db::DistanceGrid distances;
  /// The occupied voxels as boxes (runs along x merged), as triangles:
  /// for drawing and for the highest point.
  TriangleMesh mesh;

  /// Corners of the box that holds every occupied voxel (obstacle frame).
  Eigen::Vector3d low() const;
  Eigen::Vector3d high() const;
  bool isOccupied(int i, int j, int k) const;  ///< absolute voxel index
  /// Occupied voxels merged into boxes along x: centre and edge lengths.
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> boxes() const;
};

/// Most voxels (block plus border) a cloud may span: the same budget as a
/// distance grid (db::kMaxGridNodes).
inline constexpr std::uint64_t kMaxCloudVoxels = db::kMaxGridNodes;

/// The points a depth image sees, in the camera's optical frame; pixels
/// without a depth in [min_depth, max_depth], or set in `mask` (same size
/// as the image), give none. Throws hfts::InvalidArgument ("intrinsics",
/// "image", "mask") for a camera without positive focal lengths or an
/// image or mask whose size does not match.
Vertices depthToPoints(const DepthImage& image, const DepthCamera& camera,
                       const std::vector<std::uint8_t>* mask = nullptr);

/// Filters `points` (non-finite ones dropped, PCL's voxel grid at half a
/// voxel, outliers when asked) and builds the occupied voxels, their
/// distance grid and mesh. Throws hfts::InvalidArgument ("voxel",
/// "radius", "outliers", "points") for a bad option, no points left, or a
/// block over kMaxCloudVoxels.
VoxelCloud voxelize(const Vertices& points, const CloudOptions& options = {});

/// The cloud without the occupied voxels `remove` names (by absolute
/// index), its points in them dropped, its distances and mesh made again
/// (all of them: an empty cloud, no obstacle).
VoxelCloud withoutVoxels(const VoxelCloud& cloud,
                         const std::function<bool(int i, int j, int k)>& remove);

}  // namespace hfts::robot
