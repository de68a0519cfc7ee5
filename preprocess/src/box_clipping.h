#pragma once
// Triangles of a mesh clipped to an axis-aligned box: the exact boundary of
// the solid inside a cell of the convex decomposition. Private to the
// preprocess library.

#include <Eigen/Core>

#include <cstdint>
#include <functional>
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

/// Whether a point lies in the solid (for the parts of the surface that lie
/// in a face of the box).
using SolidTest = std::function<bool(const Eigen::Vector3d&)>;

/// Appends (x, y, z) of the corners of every triangle of `triangles`
/// clipped to `box` (Sutherland-Hodgman against its six planes; a point
/// made on a plane gets that plane's coordinate exactly): with the box's
/// corners in the solid, the points whose convex hull is the hull of the
/// solid in the box. What has no area in the box (a triangle outside that
/// touches it along an edge) is left out, and so is a triangle lying in a
/// face of the box unless the solid lies on the box's side of it (`solid`
/// at a point just inside the box): a cut along a face of the mesh leaves
/// that face to the side it bounds. A mesh vertex inside the box is
/// appended once, however many triangles share it.
void appendClippedCorners(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles,
                          const Box3& box, const SolidTest& solid, std::vector<double>& xyz);

/// The point `p` of the box moved a little towards the box's inside
/// (1e-6 of the box's diagonal along each axis where p is on a face), to
/// ask which side of a face the solid is on.
Eigen::Vector3d justInside(const Box3& box, const Eigen::Vector3d& p);

}  // namespace hfts::preprocess
