#pragma once
// Triangles of a mesh clipped to an axis-aligned box: the exact boundary of
// the solid inside a cell of the convex decomposition. Private to the
// preprocess library.

#include <Eigen/Core>

#include <cstdint>
#include <vector>

#include "hfts_db/triangle_mesh.h"

namespace hfts::preprocess {

/// An axis-aligned box (m).
struct Box3 {
  Eigen::Vector3d lo = Eigen::Vector3d::Zero();
  Eigen::Vector3d hi = Eigen::Vector3d::Zero();
};

/// Those of `candidates` (triangle indices of `mesh`) whose bounding box
/// meets `box` (touching counts).
std::vector<std::uint32_t> trianglesMeeting(const TriangleMesh& mesh,
                                            const std::vector<std::uint32_t>& candidates,
                                            const Box3& box);

/// Appends (x, y, z) of the corners of every triangle of `triangles`
/// clipped to `box` (Sutherland-Hodgman against its six planes; a point
/// made on a plane gets that plane's coordinate exactly): with the box's
/// corners in the solid, the points whose convex hull is the hull of the
/// solid in the box. Left out is what lies in the box's boundary: a
/// triangle outside that touches the box along an edge (no area in it), and
/// a triangle lying in a face of the box, since a cut along a face of the
/// mesh must not give that face to the side it does not bound (an arm's
/// inner face stays out of the base beside it). Such a face adds no corner
/// to the solid in the box: where the solid lies on the box's side, the
/// triangles that bound it there enter the box and bring the face's
/// corners, and the box's own corners in the solid come with them. The
/// corners of triangles wholly inside the box are appended once each,
/// however many triangles share them.
void appendClippedCorners(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles,
                          const Box3& box, std::vector<double>& xyz);

/// The point `p` of the box moved a little towards the box's inside
/// (1e-6 of the box's diagonal along each axis where p is on a face), to
/// ask which side of a face the solid is on.
Eigen::Vector3d justInside(const Box3& box, const Eigen::Vector3d& p);

}  // namespace hfts::preprocess
