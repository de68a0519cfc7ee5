// The solid split into boxes whose hulls fit it: cuts are chosen on voxels
// (cut_search.h), pieces made from the exact mesh (box_clipping.h,
// piece_hull.h), the total measured on the pieces.
#include "preprocess/convex_decomposition.h"

#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <optional>

#include "box_clipping.h"
#include "core/invalid_argument.h"
#include "cut_search.h"
#include "piece_hull.h"
#include "preprocess/convex_hull.h"
#include "solid_lattice.h"
#include "voxel_convexity.h"

namespace hfts::preprocess {
namespace {

/// One box of the decomposition.
struct Cell {
  Box3 bounds;                           ///< exact, in the object frame (m)
  VoxelBox voxels;                       ///< the lattice's voxels in it
  VoxelMeasure measure;                  ///< of those voxels
  std::vector<std::uint32_t> triangles;  ///< those whose bounding boxes meet `bounds`
  bool done = false;                     ///< no cut left
  db::ConvexPiece piece;                 ///< the hull of the solid in `bounds`, once made
  double hull = 0.0;                     ///< its volume (m^3)
  double solid = 0.0;                    ///< the lattice's measure of the solid in `bounds` (m^3)
  double excess() const { return hull - solid; }
};

void checkOptions(const DecompositionOptions& o) {
  if (o.max_parts < 1 || o.max_parts > db::kMaxConvexParts)
    throw InvalidArgument("max_parts", "must be in 1.." + std::to_string(db::kMaxConvexParts) +
                                           ", got " + std::to_string(o.max_parts));
  if (!(o.tolerance >= 0.0 && o.tolerance < 1.0))
    throw InvalidArgument("tolerance", "must be in [0, 1), got " + std::to_string(o.tolerance));
  if (o.resolution < 16 || o.resolution > 1024)
    throw InvalidArgument("resolution", "must be in 16..1024, got " + std::to_string(o.resolution));
}

double volumeOf(const db::ConvexPiece& piece) {
  return piece.vertices.rows() == 0
             ? 0.0
             : solidProperties(TriangleMesh{piece.vertices, piece.faces}).volume;
}

class Decomposer {
 public:
  Decomposer(const TriangleMesh& mesh, const DecompositionOptions& options)
      : mesh_(mesh),
        options_(options),
        lattice_(mesh, options.resolution),
        search_(lattice_, mesh) {}

  /// The cells, each with its piece: split until the pieces' volumes add
  /// up to at most 1 + tolerance times `solidVolume`, no cut is left or
  /// there are max_parts.
  std::vector<Cell> run(double solidVolume) const {
    Cell root;
    root.bounds = {mesh_.vertices.colwise().minCoeff(), mesh_.vertices.colwise().maxCoeff()};
    const VoxelSet all(lattice_, lattice_.whole());
    root.voxels = all.box();
    root.measure = all.measure();
    root.triangles.resize(static_cast<std::size_t>(mesh_.triangles.rows()));
    std::iota(root.triangles.begin(), root.triangles.end(), 0u);
    std::vector<Cell> cells{root};
    splitOnVoxels(cells);
    for (Cell& cell : cells) makePiece(cell);
    splitMeasured(cells, solidVolume);
    while (joinOnePair(cells)) {
    }
    return cells;
  }

 private:
  /// Largest voxel excess first, until the voxels' excesses add up to at
  /// most the tolerance of the solid's voxels: cheap, and it finds the
  /// cuts that matter most (a cavity, a handle, a notch).
  void splitOnVoxels(std::vector<Cell>& cells) const {
    const double total = static_cast<double>(cells.front().measure.count);
    while (cells.size() < options_.max_parts) {
      double excess = 0.0;
      std::optional<std::size_t> next;
      for (std::size_t i = 0; i < cells.size(); ++i) {
        const VoxelMeasure& m = cells[i].measure;
        excess += static_cast<double>(m.excess);
        if (!cells[i].done && m.excess > 0 && (!next || m.excess > cells[*next].measure.excess))
          next = i;
      }
      if (!next || excess <= options_.tolerance * total) return;
      const VoxelSet voxels(lattice_, cells[*next].voxels);
      const std::optional<Cut> cut = search_.choose(voxels);
      replace(cells, *next, cut ? std::optional(halves(cells[*next], voxels, *cut)) : std::nullopt);
    }
  }

  /// Largest excess of a piece over the solid in its box first, until the
  /// pieces' volumes add up to at most 1 + tolerance times the solid's:
  /// what voxels cannot see (the bulge of a hull over a thin curved wall)
  /// is measured on the pieces themselves.
  void splitMeasured(std::vector<Cell>& cells, double solidVolume) const {
    for (Cell& cell : cells) cell.done = false;
    while (cells.size() < options_.max_parts) {
      double volume = 0.0;
      std::optional<std::size_t> next;
      for (std::size_t i = 0; i < cells.size(); ++i) {
        volume += cells[i].hull;
        if (!cells[i].done && (!next || cells[i].excess() > cells[*next].excess())) next = i;
      }
      if (!next || volume <= (1.0 + options_.tolerance) * solidVolume) return;
      replace(cells, *next, measuredSplit(cells[*next]));
    }
  }

  /// Of the candidate cuts (and, if none of those helps, the fallbacks),
  /// the one whose pieces are the smallest, made; none if no cut makes
  /// them smaller than the cell's: the piece is convex as far as cuts can
  /// tell (the lattice's measure of the solid in a thin box errs by a part
  /// of a voxel, and can make a convex piece look otherwise).
  std::optional<std::array<Cell, 2>> measuredSplit(const Cell& cell) const {
    const VoxelSet voxels(lattice_, cell.voxels);
    std::optional<std::array<Cell, 2>> best;
    const auto smaller = [&](const std::vector<Cut>& cuts) {
      for (const Cut& cut : cuts) {
        std::array<Cell, 2> two = halves(cell, voxels, cut);
        for (Cell& half : two) makePiece(half);
        if (!best || two[0].hull + two[1].hull < (*best)[0].hull + (*best)[1].hull)
          best = std::move(two);
      }
      return best && (*best)[0].hull + (*best)[1].hull < cell.hull * (1.0 - 1e-9);
    };
    if (smaller(search_.candidates(voxels, cell.bounds)) || smaller(search_.fallbacks(voxels)))
      return best;
    return std::nullopt;
  }

  /// Joins the first two neighbouring cells whose boxes together are a box
  /// and whose pieces together are convex (within rounding): the halves of
  /// a flat wall that a cut nearby split on its way. Fewer parts for
  /// nothing. Whether it joined two.
  static bool joinOnePair(std::vector<Cell>& cells) {
    for (int axis = 0; axis < 3; ++axis) {
      // Cells by their extent across the other two axes and where they start.
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const auto key = [&](const Cell& c, double start) {
        return std::array<double, 5>{c.bounds.lo[u], c.bounds.hi[u], c.bounds.lo[v], c.bounds.hi[v],
                                     start};
      };
      std::map<std::array<double, 5>, std::size_t> starting;
      for (std::size_t i = 0; i < cells.size(); ++i)
        starting.emplace(key(cells[i], cells[i].bounds.lo[axis]), i);
      for (std::size_t i = 0; i < cells.size(); ++i) {
        const auto next = starting.find(key(cells[i], cells[i].bounds.hi[axis]));
        if (next == starting.end() || join(cells[i], cells[next->second]) == false) continue;
        cells.erase(cells.begin() + static_cast<std::ptrdiff_t>(next->second));
        return true;
      }
    }
    return false;
  }

  /// Makes `a` the union of `a` and `b` if their pieces' hull is no larger
  /// than the two pieces; whether it did.
  static bool join(Cell& a, const Cell& b) {
    std::vector<double> xyz;
    for (const db::ConvexPiece* piece : {static_cast<const db::ConvexPiece*>(&a.piece), &b.piece})
      for (Eigen::Index i = 0; i < piece->vertices.rows(); ++i)
        xyz.insert(xyz.end(),
                   {piece->vertices(i, 0), piece->vertices(i, 1), piece->vertices(i, 2)});
    db::ConvexPiece joined = pieceHull(std::move(xyz));
    const double hull = volumeOf(joined);
    if (hull > (a.hull + b.hull) * (1.0 + 1e-9)) return false;
    a.bounds.lo = a.bounds.lo.cwiseMin(b.bounds.lo);
    a.bounds.hi = a.bounds.hi.cwiseMax(b.bounds.hi);
    a.piece = std::move(joined);
    a.hull = hull;
    a.solid += b.solid;
    return true;
  }

  /// Puts the halves in place of cell i, or marks it done if there are none.
  static void replace(std::vector<Cell>& cells, std::size_t i,
                      std::optional<std::array<Cell, 2>> two) {
    if (!two) {
      cells[i].done = true;
      return;
    }
    cells[i] = std::move((*two)[0]);
    cells.push_back(std::move((*two)[1]));
  }

  /// The cell cut in two, pieces not made.
  std::array<Cell, 2> halves(const Cell& cell, const VoxelSet& voxels, const Cut& cut) const {
    std::array<Cell, 2> out;
    const std::array<VoxelBox, 2> boxes = halvesOf(voxels.box(), cut);
    for (std::size_t s = 0; s < 2; ++s) {
      out[s].bounds = cell.bounds;
      out[s].voxels = boxes[s];
      out[s].measure = cut.sides[s];
    }
    out[0].bounds.hi[cut.axis] = cut.coordinate;
    out[1].bounds.lo[cut.axis] = cut.coordinate;
    for (Cell& half : out) half.triangles = trianglesMeeting(mesh_, cell.triangles, half.bounds);
    return out;
  }

  /// The hull of the solid in the cell's box (the mesh clipped to it and
  /// the box's corners in the solid), its volume and the solid's.
  void makePiece(Cell& cell) const {
    const Box3& box = cell.bounds;
    std::vector<double> xyz;
    appendClippedCorners(mesh_, cell.triangles, box, xyz);
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3d p((corner & 1) ? box.hi.x() : box.lo.x(),
                              (corner & 2) ? box.hi.y() : box.lo.y(),
                              (corner & 4) ? box.hi.z() : box.lo.z());
      // A corner on the surface counts if the solid is on the box's side.
      if (lattice_.contains(justInside(box, p))) xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
    }
    cell.piece = pieceHull(std::move(xyz));
    cell.hull = volumeOf(cell.piece);
    cell.solid = lattice_.volumeIn(box.lo, box.hi);
  }

  const TriangleMesh& mesh_;
  DecompositionOptions options_;
  SolidLattice lattice_;
  CutSearch search_;
};

}  // namespace

ConvexDecomposition decomposeConvex(const TriangleMesh& mesh, bool closed,
                                    const DecompositionOptions& options, const std::string& what) {
  checkOptions(options);
  ConvexDecomposition out;
  const double smallest = db::minimumConvexPartVolume(mesh.vertices.colwise().minCoeff(),
                                                      mesh.vertices.colwise().maxCoeff());
  if (closed) {
    out.solid_volume = solidVolume(mesh);
    for (Cell& cell : Decomposer(mesh, options).run(out.solid_volume))
      if (cell.hull >= smallest) out.parts.push_back(std::move(cell.piece));
  }
  if (out.parts.empty()) out.parts.push_back(canonicalHull(mesh.vertices, what));
  for (const db::ConvexPiece& part : out.parts) out.parts_volume += volumeOf(part);
  return out;
}

}  // namespace hfts::preprocess
