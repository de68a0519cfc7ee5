#pragma once
// Where to cut a box of the convex decomposition: the planes across x, y or
// z that leave the halves nearest convex, measured on voxels
// (voxel_convexity.h). Private to the preprocess library.

#include <array>
#include <optional>
#include <vector>

#include "box_clipping.h"
#include "hfts_db/triangle_mesh.h"
#include "solid_lattice.h"
#include "voxel_convexity.h"

namespace hfts::preprocess {

/// A plane across one axis, between two layers of voxels (or on a flat face
/// of the mesh near there).
struct Cut {
  int axis = 0;
  int at = 0;                         ///< voxel index: the voxels before it are below the cut
  double coordinate = 0.0;            ///< where the plane runs (m)
  std::array<VoxelMeasure, 2> sides;  ///< the voxels below and above
  double score = 0.0;                 ///< what chose it: less is better
};

/// The two boxes of voxels a cut leaves.
std::array<VoxelBox, 2> halvesOf(const VoxelBox& box, const Cut& cut);

class CutSearch {
 public:
  /// Keeps references to both; the mesh gives the flat faces a cut may
  /// snap to.
  CutSearch(const SolidLattice& lattice, const TriangleMesh& mesh);

  /// The cut that takes the most excess away (summed over the halves),
  /// the more balanced of equals, if it takes a tenth of the voxels'
  /// excess away; otherwise (a ring, a cup: no single cut helps) the one of
  /// each axis's best whose halves are nearest convex after one more cut
  /// each. None when the voxels are too few to cut.
  std::optional<Cut> choose(const VoxelSet& voxels) const;

  /// Cuts worth measuring on the exact pieces of a box with these bounds
  /// (m): choose()'s, the most balanced across each axis (the voxels cannot
  /// tell which way a thin curved wall bends: every cut leaves them
  /// digitally convex), and cuts that part the voxels from solid no voxel
  /// centre lies in (a sliver of a tube's side, far across the box). A box
  /// without voxels is halved across each axis at least two voxels long.
  std::vector<Cut> candidates(const VoxelSet& voxels, const Box3& bounds) const;

  /// More cuts to measure when none of candidates() gives smaller pieces
  /// (the voxels see nothing to cut, as at a bottle's shoulder): across
  /// each axis at an eighth, a quarter, three quarters and seven eighths
  /// of the voxels.
  std::vector<Cut> fallbacks(const VoxelSet& voxels) const;

 private:
  std::optional<Cut> best(const VoxelSet& voxels, int axis) const;
  std::optional<Cut> balanced(const VoxelSet& voxels, int axis) const;
  std::optional<Cut> at(const VoxelSet& voxels,
                        const std::vector<std::array<VoxelMeasure, 2>>& cuts, int axis,
                        int index) const;
  std::optional<double> flatPlaneNear(int axis, int index) const;
  std::int64_t excessAfterOneCut(const VoxelBox& box, std::int64_t excess) const;
  void appendTrims(const VoxelSet& voxels, const Box3& bounds, std::vector<Cut>& out) const;

  const SolidLattice& lattice_;
  std::array<std::vector<double>, 3> planes_;  ///< flat faces of the mesh, per axis, sorted
};

}  // namespace hfts::preprocess
