#pragma once
// The convex hull of a point cloud as a closed polytope (Qhull), private to
// the preprocess library: the pieces of the convex decomposition.

#include <vector>

#include "hfts_db/object_database.h"

namespace hfts::preprocess {

/// The convex hull of the points (x, y, z, x, y, z, ...): its vertices
/// sorted lexicographically, each facet (Qhull merges coplanar ones) a fan
/// of triangles from its smallest vertex, counter-clockwise seen from
/// outside, the triangles sorted. Qhull draws nothing at random and does not
/// depend on memory addresses, so the same points in the same order give the
/// same piece. No vertices when the points span no volume.
db::ConvexPiece pieceHull(std::vector<double> xyz);

}  // namespace hfts::preprocess
