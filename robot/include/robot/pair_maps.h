#pragma once
// Joint-space maps of link pairs that are apart (docs/collision.md): for two
// links whose relative pose depends on one to three DoFs (a wrist's forearm
// and flange, two fingers of a hand), a grid over those DoFs' limits with a
// bit per cell, set when no sphere of one link can touch a sphere of the
// other anywhere in the cell. The sphere tier looks a pair up before it
// descends the pair's sphere trees.

#include <Eigen/Core>

#include <cstdint>
#include <vector>

#include "robot/robot_model.h"

namespace hfts::robot {

struct SphereModel;  // link_spheres.h

struct PairMapOptions {
  /// Distance (m) by which the spheres must be apart, on top of the
  /// movement within a cell: the sphere tier pads each of its spheres by
  /// 0.5 mm, so a cell set here is apart by that tier's own test too.
  double clearance = 1e-3;
  /// Cells along the DoF of a one-DoF pair, and along each DoF of a two-
  /// and a three-DoF pair.
  int cells_one = 512;
  int cells_two = 128;
  int cells_three = 32;
};

/// The cells of one link pair in which its spheres are proven apart.
struct PairMap {
  static constexpr int kMaxDofs = 3;
  int link_a = -1;
  int link_b = -1;
  /// The DoFs the pair's relative pose depends on, ascending; -1 after the last.
  int dofs[kMaxDofs] = {-1, -1, -1};
  double lower[kMaxDofs] = {0, 0, 0};  ///< lower limit of each DoF
  double width[kMaxDofs] = {1, 1, 1};  ///< a cell's width along each DoF (rad)
  int cells[kMaxDofs] = {1, 1, 1};     ///< 1 for an unused DoF
  /// Bit i0 + cells[0] (i1 + cells[1] i2) (word / 32, bit % 32): cell
  /// (i0, i1, i2) is apart.
  std::vector<std::uint32_t> apart;

  /// True when q lies in a cell set apart (false outside the limits).
  bool provesApart(const Eigen::VectorXd& q) const;
  /// The share of cells set apart.
  double apartShare() const;
};

/// Maps for every link pair whose collision is not disabled, whose links
/// both have spheres, whose relative pose depends on one to three DoFs
/// through revolute joints only, and that are apart somewhere. A cell is
/// set when the spheres (in `spheres`) are apart by `clearance` plus a bound
/// on how far any point of them moves while the DoFs vary over the cell (grown by 1e-4 rad each
/// side, for rounding in the kernels' lookup): angle times distance from the
/// joint's axis, summed over the joints between the two links. Built
/// coarse to fine: a block of cells proven apart as a whole is not split.
/// Deterministic.
std::vector<PairMap> buildPairMaps(const RobotModel& model, const SphereModel& spheres,
                                   const PairMapOptions& options = {});

}  // namespace hfts::robot
