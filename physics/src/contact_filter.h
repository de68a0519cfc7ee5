#pragma once
// Private to physics/src: a tighter test than MuJoCo 2.2's before its
// narrow phase (mjcb_contactfilter). MuJoCo 2.2 has no midphase inside a
// body pair: every geom pair whose bounding spheres overlap goes to the
// convex narrow phase. A bowl stored as 353 convex parts standing on a table
// top (a box whose bounding sphere is metres wide) sends all 353 parts to
// MPR at every step. The filter drops a pair when one geom's bounding
// sphere is farther than the pair's margin from the other's exact shape
// (box, capsule, cylinder, sphere): such a pair has no contact, so the
// simulation is the same, only faster.

#include <mujoco/mujoco.h>

namespace hfts::physics {

/// MuJoCo's contact filter callback (1: discard the pair). It first applies
/// the contype/conaffinity rule that a user filter replaces, then the
/// sphere-against-shape test above.
int filterContactPair(const mjModel* m, mjData* d, int geom1, int geom2);

/// The distance (m) from a sphere (centre, radius) to geom `geom`'s shape
/// where `d` has it: exact for a box, capsule, cylinder, sphere and (as its
/// bounding box) an ellipsoid; for other types a lower bound from the
/// geom's bounding sphere; negative when they overlap.
double sphereToGeom(const mjModel& m, const mjData& d, int geom, const mjtNum centre[3],
                    mjtNum radius);

}  // namespace hfts::physics
