// Inside/outside of grid nodes: the winding number along the grid lines
// through them (windingLines), one vote per axis.
#include "grid_winding.h"

#include <array>
#include <cstddef>

#include "hfts_db/winding_lines.h"

namespace hfts::db {
namespace {

/// Adds 1 to votes[node] for every node whose winding number along its
/// line parallel to `axis` is not 0.
void vote(const TriangleMesh& mesh, const DistanceGrid& grid, int axis,
          std::vector<std::uint8_t>& votes) {
  LineLattice lattice;
  lattice.axis = axis;
  lattice.origin = grid.origin;
  lattice.spacing = grid.spacing;
  lattice.counts = {grid.dims[static_cast<std::size_t>(lattice.u())],
                    grid.dims[static_cast<std::size_t>(lattice.v())]};
  const WindingLines lines = windingLines(mesh, lattice);
  std::array<std::uint32_t, 3> n;
  const auto a = static_cast<std::size_t>(axis);
  for (std::uint32_t j = 0; j < lattice.counts[1]; ++j)
    for (std::uint32_t i = 0; i < lattice.counts[0]; ++i) {
      const std::size_t line = lattice.index(i, j);
      n[static_cast<std::size_t>(lattice.u())] = i;
      n[static_cast<std::size_t>(lattice.v())] = j;
      const Interval* s = lines.begin(line);
      for (std::uint32_t k = 0; k < grid.dims[a] && s != lines.end(line); ++k) {
        const double at = grid.coordinate(axis, k);
        while (s != lines.end(line) && s->exit < at) ++s;
        if (s == lines.end(line) || !(s->enter < at)) continue;
        n[a] = k;
        ++votes[grid.index(n[0], n[1], n[2])];
      }
    }
}

}  // namespace

std::vector<std::uint8_t> insideNodes(const TriangleMesh& mesh, const DistanceGrid& grid) {
  std::vector<std::uint8_t> votes(
      std::size_t{grid.dims[0]} * std::size_t{grid.dims[1]} * std::size_t{grid.dims[2]}, 0);
  for (int axis = 0; axis < 3; ++axis) vote(mesh, grid, axis, votes);
  for (std::uint8_t& v : votes) v = v >= 2 ? 1 : 0;
  return votes;
}

}  // namespace hfts::db
