#include "box_clipping.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>

namespace hfts::preprocess {
namespace {

/// A convex polygon while it is clipped: a triangle cut by six planes has
/// at most 9 corners.
struct Polygon {
  std::array<Eigen::Vector3d, 12> corner;
  int size = 0;
};

/// Keeps the part of `in` with x[axis] >= bound (keepAbove) or <= bound.
Polygon clip(const Polygon& in, int axis, double bound, bool keepAbove) {
  Polygon out;
  const auto keeps = [&](const Eigen::Vector3d& p) {
    return keepAbove ? p[axis] >= bound : p[axis] <= bound;
  };
  for (int k = 0; k < in.size; ++k) {
    const Eigen::Vector3d& a = in.corner[static_cast<std::size_t>(k)];
    const Eigen::Vector3d& b = in.corner[static_cast<std::size_t>((k + 1) % in.size)];
    if (keeps(a)) out.corner[static_cast<std::size_t>(out.size++)] = a;
    if (keeps(a) == keeps(b)) continue;
    Eigen::Vector3d p = a + (b - a) * ((bound - a[axis]) / (b[axis] - a[axis]));
    p[axis] = bound;  // on the plane, whatever the rounding
    out.corner[static_cast<std::size_t>(out.size++)] = p;
  }
  return out;
}

/// Strictly inside: a triangle with a corner on a face may lie in it.
bool strictlyInside(const Box3& box, const Eigen::Vector3d& p) {
  return (p.array() > box.lo.array()).all() && (p.array() < box.hi.array()).all();
}

/// Whether the polygon encloses area (clipping leaves only an edge or a
/// point of a triangle that touches the box from outside).
bool hasArea(const Polygon& polygon) {
  if (polygon.size < 3) return false;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double extent = 0.0;
  const Eigen::Vector3d& a = polygon.corner[0];
  for (int k = 1; k + 1 < polygon.size; ++k) {
    const Eigen::Vector3d u = polygon.corner[static_cast<std::size_t>(k)] - a;
    normal += u.cross(polygon.corner[static_cast<std::size_t>(k + 1)] - a);
    extent = std::max(extent, u.squaredNorm());
  }
  return normal.norm() > 1e-12 * extent;
}

/// Whether every corner lies in one face plane of the box.
bool onFace(const Box3& box, const Polygon& polygon) {
  for (int axis = 0; axis < 3; ++axis)
    for (double bound : {box.lo[axis], box.hi[axis]}) {
      bool all = true;
      for (int k = 0; k < polygon.size && all; ++k)
        all = polygon.corner[static_cast<std::size_t>(k)][axis] == bound;
      if (all) return true;
    }
  return false;
}

}  // namespace

std::vector<std::uint32_t> trianglesMeeting(const TriangleMesh& mesh,
                                            const std::vector<std::uint32_t>& candidates,
                                            const Box3& box) {
  std::vector<std::uint32_t> out;
  for (std::uint32_t t : candidates) {
    Eigen::Vector3d lo = mesh.vertices.row(mesh.triangles(t, 0)).transpose(), hi = lo;
    for (int k = 1; k < 3; ++k) {
      lo = lo.cwiseMin(mesh.vertices.row(mesh.triangles(t, k)).transpose());
      hi = hi.cwiseMax(mesh.vertices.row(mesh.triangles(t, k)).transpose());
    }
    if ((lo.array() <= box.hi.array()).all() && (hi.array() >= box.lo.array()).all())
      out.push_back(t);
  }
  return out;
}

Eigen::Vector3d justInside(const Box3& box, const Eigen::Vector3d& p) {
  const double step = 1e-6 * (box.hi - box.lo).norm();
  Eigen::Vector3d q = p;
  for (int c = 0; c < 3; ++c) {
    if (p[c] <= box.lo[c]) q[c] += step;
    if (p[c] >= box.hi[c]) q[c] -= step;
  }
  return q;
}

void appendClippedCorners(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles,
                          const Box3& box, std::vector<double>& xyz) {
  std::vector<bool> added(static_cast<std::size_t>(mesh.vertices.rows()), false);
  for (std::uint32_t t : triangles) {
    Polygon polygon;
    bool whole = true;
    for (int k = 0; k < 3; ++k) {
      polygon.corner[static_cast<std::size_t>(k)] = mesh.vertices.row(mesh.triangles(t, k));
      whole = whole && strictlyInside(box, polygon.corner[static_cast<std::size_t>(k)]);
    }
    polygon.size = 3;
    if (whole) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = mesh.triangles(t, k);
        if (added[v]) continue;
        added[v] = true;
        xyz.insert(xyz.end(), {mesh.vertices(v, 0), mesh.vertices(v, 1), mesh.vertices(v, 2)});
      }
      continue;
    }
    for (int axis = 0; axis < 3 && polygon.size > 0; ++axis) {
      polygon = clip(polygon, axis, box.lo[axis], true);
      polygon = clip(polygon, axis, box.hi[axis], false);
    }
    if (!hasArea(polygon) || onFace(box, polygon)) continue;
    for (int k = 0; k < polygon.size; ++k) {
      const Eigen::Vector3d& p = polygon.corner[static_cast<std::size_t>(k)];
      xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
    }
  }
}

}  // namespace hfts::preprocess
