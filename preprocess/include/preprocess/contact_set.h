#pragma once
// Candidate fingertip contacts while they are being filtered.

#include <Eigen/Core>

#include <cstdint>
#include <vector>

#include "hfts_db/triangle_mesh.h"

namespace hfts::preprocess {

/// Contacts in the object frame; normals are unit vectors pointing out of
/// the object. All members have one row / entry per contact.
struct ContactSet {
  Vertices positions;
  Vertices normals;
  Eigen::VectorXd curvature;  ///< PCL surface variation, in [0, 1/3]

  std::size_t size() const { return static_cast<std::size_t>(positions.rows()); }
  /// Keeps the contacts whose mask entry is true, in order.
  void keep(const std::vector<bool>& mask);
};

/// Smoothed normals and curvature by PCL's normal estimation
/// (pcl::computePointNormal) over the points of `support` within
/// `patch_radius` that were seen from the same side (side normals less than
/// 120 degrees apart), oriented to agree with `sideNormals` (the outward
/// side each sample was seen from). The support is a sampling of the same
/// surface dense enough for a patch to hold tens of points whatever the
/// contacts' density (a plane fitted to ten points tells an edge from a
/// face by chance). Points with fewer than three such neighbours keep their
/// side normal and get the largest curvature, 1/3.
struct SurfacePoints {
  Vertices positions;
  Vertices sides;  ///< the outward side each point was seen from
};
ContactSet estimateNormals(const Vertices& positions, const Vertices& sideNormals,
                           const SurfacePoints& support, double patch_radius);

/// The same with the contacts as their own support.
ContactSet estimateNormals(const Vertices& positions, const Vertices& sideNormals,
                           double patch_radius);

}  // namespace hfts::preprocess
