// A sphere-against-shape test before MuJoCo's narrow phase (contact_filter.h).
#include "contact_filter.h"

#include <algorithm>
#include <cmath>

namespace hfts::physics {
namespace {

/// `point` in the frame of geom `geom`.
void toGeomFrame(const mjData& d, int geom, const mjtNum point[3], mjtNum local[3]) {
  const mjtNum* origin = d.geom_xpos + 3 * geom;
  const mjtNum* r = d.geom_xmat + 9 * geom;  // row-major: the columns are the geom's axes
  const mjtNum x = point[0] - origin[0], y = point[1] - origin[1], z = point[2] - origin[2];
  local[0] = r[0] * x + r[3] * y + r[6] * z;
  local[1] = r[1] * x + r[4] * y + r[7] * z;
  local[2] = r[2] * x + r[5] * y + r[8] * z;
}

/// Distance from a point (in a box's frame) to a box of half extents h.
double pointToBox(const mjtNum p[3], double hx, double hy, double hz) {
  const double dx = std::max(std::abs(p[0]) - hx, 0.0);
  const double dy = std::max(std::abs(p[1]) - hy, 0.0);
  const double dz = std::max(std::abs(p[2]) - hz, 0.0);
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

/// Whether geom `shape`'s exact shape is farther than `margin` from the
/// bounding sphere of geom `other`.
bool separated(const mjModel& m, const mjData& d, int shape, int other, mjtNum margin) {
  const mjtNum radius = m.geom_rbound[other];
  if (!(radius > 0.0)) return false;  // a plane or height field: unbounded
  return sphereToGeom(m, d, shape, d.geom_xpos + 3 * other, radius) > margin;
}

}  // namespace

double sphereToGeom(const mjModel& m, const mjData& d, int geom, const mjtNum centre[3],
                    mjtNum radius) {
  const mjtNum* size = m.geom_size + 3 * geom;
  mjtNum p[3];
  toGeomFrame(d, geom, centre, p);
  switch (m.geom_type[geom]) {
    case mjGEOM_BOX:
    case mjGEOM_ELLIPSOID:  // inside the box of its semi-axes
      return pointToBox(p, size[0], size[1], size[2]) - radius;
    case mjGEOM_CAPSULE: {
      const double t = std::clamp(p[2], -size[1], size[1]);
      return std::sqrt(p[0] * p[0] + p[1] * p[1] + (p[2] - t) * (p[2] - t)) - size[0] - radius;
    }
    case mjGEOM_CYLINDER: {
      const double radial = std::max(std::sqrt(p[0] * p[0] + p[1] * p[1]) - size[0], 0.0);
      const double axial = std::max(std::abs(p[2]) - size[1], 0.0);
      return std::sqrt(radial * radial + axial * axial) - radius;
    }
    case mjGEOM_SPHERE:
      return mju_norm3(p) - size[0] - radius;
    default: {
      const mjtNum bound = m.geom_rbound[geom];
      if (!(bound > 0.0)) return -1.0;  // unbounded: they may touch
      return mju_norm3(p) - bound - radius;
    }
  }
}

int filterContactPair(const mjModel* m, mjData* d, int geom1, int geom2) {
  // The rule MuJoCo applies when no user filter is set.
  if (!(m->geom_contype[geom1] & m->geom_conaffinity[geom2]) &&
      !(m->geom_contype[geom2] & m->geom_conaffinity[geom1]))
    return 1;
  const mjtNum margin = std::max(m->geom_margin[geom1], m->geom_margin[geom2]);
  // MuJoCo's own bounding-sphere test first (it follows the filter): most
  // pairs end here, and it is the cheapest.
  const mjtNum r1 = m->geom_rbound[geom1], r2 = m->geom_rbound[geom2];
  if (r1 > 0.0 && r2 > 0.0) {
    const mjtNum* a = d->geom_xpos + 3 * geom1;
    const mjtNum* b = d->geom_xpos + 3 * geom2;
    const mjtNum dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    const mjtNum reach = r1 + r2 + margin;
    if (dx * dx + dy * dy + dz * dz > reach * reach) return 1;
  }
  return separated(*m, *d, geom1, geom2, margin) || separated(*m, *d, geom2, geom1, margin) ? 1 : 0;
}

}  // namespace hfts::physics
