#pragma once
// The solid of a closed mesh (where its winding number is not 0) on a
// regular lattice of voxels: which voxel centres are in it, and whether any
// point is. Private to the preprocess library (the convex decomposition).

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

#include "hfts_db/triangle_mesh.h"
#include "hfts_db/winding_lines.h"

namespace hfts::preprocess {

/// A box of voxels: index ranges lo..hi (inclusive) along x, y and z.
struct VoxelBox {
  std::array<int, 3> lo{0, 0, 0};
  std::array<int, 3> hi{-1, -1, -1};
  int size(int axis) const {
    return hi[static_cast<std::size_t>(axis)] - lo[static_cast<std::size_t>(axis)] + 1;
  }
};

/// A run of solid voxels along a vertical line: levels first..last.
struct LevelRun {
  int first = 0;
  int last = -1;
};

/// Cubic voxels of edge spacing(); voxel (i, j, k) is centred at
/// centre(0, i), centre(1, j), centre(2, k). The lattice starts half a
/// voxel before the mesh's bounding box and ends at least half a voxel
/// beyond it, so no voxel centre lies on a face of the box.
class SolidLattice {
 public:
  /// `resolution` voxels along the longest side of the mesh's bounding
  /// box. The mesh must outlive the lattice. Precondition: a mesh with
  /// triangles and finite vertices that spans more than a point.
  SolidLattice(const TriangleMesh& mesh, std::uint32_t resolution);

  double spacing() const { return spacing_; }
  double centre(int axis, int i) const { return origin_[axis] + spacing_ * i; }
  /// The face between voxels i - 1 and i along `axis`.
  double face(int axis, int i) const { return centre(axis, i) - 0.5 * spacing_; }
  VoxelBox whole() const;

  /// The runs of voxels of column (i, j) within levels k0..k1 whose
  /// centres are in the solid, bottom up.
  void runs(int i, int j, int k0, int k1, std::vector<LevelRun>& out) const;
  /// Volume of the solid in the box [lo, hi] (m^3): exact along the
  /// vertical lines through the voxel centres, each standing for its
  /// voxel's square (the part of it inside the box).
  double volumeIn(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const;
  /// Whether the point lies in the solid: the winding number along the
  /// vertical line through p, counted over the triangles whose bounding
  /// boxes reach that line (windingLines' rule: a point on the surface is
  /// inside when the line reaches it from inside, going up).
  bool contains(const Eigen::Vector3d& p) const;

 private:
  /// The voxel index along `axis` (0 or 1) whose slab holds x, clamped.
  int column(int axis, double x) const;

  const TriangleMesh& mesh_;
  Eigen::Vector3d origin_;
  double spacing_ = 0.0;
  std::array<int, 3> count_{0, 0, 0};
  db::WindingLines centres_;  ///< through voxel centres
  /// Per column of voxels (index i + nx * j), the triangles whose bounding
  /// boxes reach into it across x and y.
  std::vector<std::vector<std::uint32_t>> columns_;
};

}  // namespace hfts::preprocess
