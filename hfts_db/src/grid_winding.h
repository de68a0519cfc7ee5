#pragma once
// Which nodes of a distance grid lie inside a closed mesh, private to
// hfts_db (used by buildDistanceGrid, tested through it).

#include <cstdint>
#include <vector>

#include "hfts_db/distance_grid.h"
#include "hfts_db/triangle_mesh.h"

namespace hfts::db {

/// For every node of `grid` (its layout only; index() order), 1 where the
/// winding number of `mesh` is not 0, else 0. The winding number is counted
/// along the grid lines parallel to each axis (signed crossings, a point on
/// an edge or vertex belonging to exactly one of the triangles that share
/// it); a node is inside when at least two of its three lines say so.
/// Overlapping closed parts and inward winding are both handled.
std::vector<std::uint8_t> insideNodes(const TriangleMesh& mesh, const DistanceGrid& grid);

}  // namespace hfts::db
