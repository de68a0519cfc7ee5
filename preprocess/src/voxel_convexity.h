#pragma once
// How far the solid voxels of a box are from convex, and how far each half
// of every axis-aligned cut of the box would be: the convex decomposition's
// measure for choosing cuts. Private to the preprocess library.
//
// The measure is digital and exact: a slab of voxels (one layer across an
// axis) is digitally convex when every voxel centre inside the convex hull
// of its solid voxels' centres is solid. The slab's excess is the number of
// such centres that are not (Pick's theorem counts them from the hull's
// area and boundary); a box's excess is the largest over the three slab
// directions of the summed excesses. A convex solid has excess 0 exactly;
// a cup's cavity, a ring's hole, an L's notch count their voxels.

#include <array>
#include <cstdint>
#include <vector>

#include "solid_lattice.h"

namespace hfts::preprocess {

/// Voxel count and excess of a set of voxels.
struct VoxelMeasure {
  std::int64_t count = 0;
  std::int64_t excess = 0;
};

/// The solid voxels in one box of a lattice.
class VoxelSet {
 public:
  VoxelSet(const SolidLattice& lattice, const VoxelBox& box);

  /// The box the set was made of.
  const VoxelBox& frame() const { return frame_; }
  /// The smallest box holding the solid voxels (empty: hi < lo).
  const VoxelBox& box() const { return box_; }
  const VoxelMeasure& measure() const { return measure_; }
  /// For every cut across `axis` before voxel index frame().lo + m, 0 < m <
  /// frame().size(axis): the two sides (below: indices before it, above:
  /// from it), at element m - 1.
  std::vector<std::array<VoxelMeasure, 2>> cuts(int axis) const;

 private:
  /// Extremes [min, max] along the third axis of the voxels in slab `s` of
  /// `slabAxis` at index `t` of `sweepAxis` (box-relative); min > max if none.
  std::array<int, 2> extent(int slabAxis, int sweepAxis, int s, int t) const;
  /// Per index along `sweepAxis`: the lattice points of the hulls of every
  /// slab across `slabAxis`, restricted to indices <= it (or >= it).
  std::vector<std::int64_t> sweep(int slabAxis, int sweepAxis, bool reverse) const;
  VoxelMeasure measureAll() const;

  VoxelBox frame_;
  VoxelBox box_;
  std::array<int, 3> n_{0, 0, 0};
  std::vector<std::array<int, 2>> xOfZY_;            ///< (k, j) -> i extremes
  std::vector<std::array<int, 2>> yOfZX_;            ///< (k, i) -> j extremes
  std::vector<std::array<int, 2>> zOfXY_;            ///< (i, j) -> k extremes
  std::array<std::vector<std::int64_t>, 3> counts_;  ///< voxels per slab, per axis
  VoxelMeasure measure_;
};

}  // namespace hfts::preprocess
