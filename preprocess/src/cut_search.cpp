#include "cut_search.h"

#include <algorithm>
#include <cmath>

namespace hfts::preprocess {
namespace {

/// No cut leaves fewer than this many layers of solid voxels on a side.
constexpr int kMinLayers = 2;
/// Cuts that leave two similar halves are preferred, by this weight per
/// voxel of difference, where no cut makes the halves more convex (a ring,
/// a cup): the next cuts then do.
constexpr double kBalanceWeight = 0.05;

/// Per axis, the sorted coordinates of the mesh's faces that lie in a plane
/// across that axis: a cut there leaves such a face whole.
std::array<std::vector<double>, 3> flatPlanes(const TriangleMesh& mesh) {
  std::array<std::vector<double>, 3> planes;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
    for (int c = 0; c < 3; ++c) {
      const double x = mesh.vertices(mesh.triangles(t, 0), c);
      if (mesh.vertices(mesh.triangles(t, 1), c) == x &&
          mesh.vertices(mesh.triangles(t, 2), c) == x)
        planes[static_cast<std::size_t>(c)].push_back(x);
    }
  for (std::vector<double>& p : planes) {
    std::sort(p.begin(), p.end());
    p.erase(std::unique(p.begin(), p.end()), p.end());
  }
  return planes;
}

std::int64_t excessOf(const Cut& cut) {
  return cut.sides[0].excess + cut.sides[1].excess;
}

}  // namespace

std::array<VoxelBox, 2> halvesOf(const VoxelBox& box, const Cut& cut) {
  std::array<VoxelBox, 2> out{box, box};
  out[0].hi[static_cast<std::size_t>(cut.axis)] = cut.at - 1;
  out[1].lo[static_cast<std::size_t>(cut.axis)] = cut.at;
  return out;
}

CutSearch::CutSearch(const SolidLattice& lattice, const TriangleMesh& mesh)
    : lattice_(lattice), planes_(flatPlanes(mesh)) {}

std::optional<Cut> CutSearch::at(const VoxelSet& voxels,
                                 const std::vector<std::array<VoxelMeasure, 2>>& cuts, int axis,
                                 int index) const {
  const auto a = static_cast<std::size_t>(axis);
  if (index < voxels.box().lo[a] + kMinLayers || index > voxels.box().hi[a] + 1 - kMinLayers)
    return std::nullopt;
  const auto& s = cuts[static_cast<std::size_t>(index - voxels.frame().lo[a] - 1)];
  if (s[0].count == 0 || s[1].count == 0) return std::nullopt;
  const double score = static_cast<double>(s[0].excess + s[1].excess) +
                       kBalanceWeight * static_cast<double>(std::abs(s[0].count - s[1].count));
  return Cut{axis, index, lattice_.face(axis, index), s, score};
}

std::optional<Cut> CutSearch::best(const VoxelSet& voxels, int axis) const {
  // The best cut between voxel layers, then moved onto a flat face of the
  // mesh within a voxel and a half, if there is one: so an L's arms become
  // exact boxes (the voxels cannot tell those cuts apart).
  const auto a = static_cast<std::size_t>(axis);
  const std::vector<std::array<VoxelMeasure, 2>> cuts = voxels.cuts(axis);
  std::optional<Cut> out;
  for (int index = voxels.box().lo[a]; index <= voxels.box().hi[a]; ++index) {
    const std::optional<Cut> cut = at(voxels, cuts, axis, index);
    if (cut && (!out || cut->score < out->score)) out = cut;
  }
  if (!out) return out;
  const std::optional<double> plane = flatPlaneNear(axis, out->at);
  if (!plane) return out;
  int index = out->at - 1;  // the first voxel whose centre is not below the plane
  while (lattice_.centre(axis, index) < *plane) ++index;
  std::optional<Cut> snapped = at(voxels, cuts, axis, index);
  if (!snapped) return out;
  snapped->coordinate = *plane;
  return snapped;
}

std::optional<double> CutSearch::flatPlaneNear(int axis, int index) const {
  const double face = lattice_.face(axis, index);
  const std::vector<double>& planes = planes_[static_cast<std::size_t>(axis)];
  const double lo = lattice_.centre(axis, index - 2), hi = lattice_.centre(axis, index + 1);
  std::optional<double> out;
  for (auto p = std::upper_bound(planes.begin(), planes.end(), lo); p != planes.end() && *p < hi;
       ++p)
    if (!out || std::abs(*p - face) < std::abs(*out - face)) out = *p;
  return out;
}

std::optional<Cut> CutSearch::balanced(const VoxelSet& voxels, int axis) const {
  const auto a = static_cast<std::size_t>(axis);
  const std::vector<std::array<VoxelMeasure, 2>> cuts = voxels.cuts(axis);
  std::optional<Cut> out;
  for (int index = voxels.box().lo[a]; index <= voxels.box().hi[a]; ++index) {
    std::optional<Cut> cut = at(voxels, cuts, axis, index);
    if (!cut) continue;
    cut->score = static_cast<double>(std::abs(cut->sides[0].count - cut->sides[1].count));
    if (!out || cut->score < out->score) out = cut;
  }
  return out;
}

std::int64_t CutSearch::excessAfterOneCut(const VoxelBox& box, std::int64_t excess) const {
  const VoxelSet voxels(lattice_, box);
  for (int axis = 0; axis < 3; ++axis)
    if (const std::optional<Cut> cut = best(voxels, axis))
      excess = std::min(excess, excessOf(*cut));
  return excess;
}

std::optional<Cut> CutSearch::choose(const VoxelSet& voxels) const {
  const std::array<std::optional<Cut>, 3> cuts = {best(voxels, 0), best(voxels, 1),
                                                  best(voxels, 2)};
  std::optional<Cut> out;
  for (const std::optional<Cut>& c : cuts)
    if (c && (!out || c->score < out->score)) out = c;
  const std::int64_t excess = voxels.measure().excess;
  if (!out || 10 * (excess - excessOf(*out)) >= excess) return out;
  std::int64_t ahead = 0;
  out.reset();
  for (const std::optional<Cut>& c : cuts) {
    if (!c) continue;
    const std::array<VoxelBox, 2> halves = halvesOf(voxels.box(), *c);
    const std::int64_t e = excessAfterOneCut(halves[0], c->sides[0].excess) +
                           excessAfterOneCut(halves[1], c->sides[1].excess);
    if (!out || e < ahead) {
      out = c;
      ahead = e;
    }
  }
  return out;
}

void CutSearch::appendTrims(const VoxelSet& voxels, const Box3& bounds,
                            std::vector<Cut>& out) const {
  const double h = lattice_.spacing();
  const VoxelBox& v = voxels.box();
  const VoxelMeasure whole = voxels.measure(), none{};
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<std::size_t>(axis);
    const double lo = bounds.lo[axis], hi = bounds.hi[axis];
    if (whole.count == 0) {
      if (hi - lo >= 2 * h) out.push_back({axis, v.lo[a], 0.5 * (lo + hi), {none, none}, 0.0});
      continue;
    }
    if (lo < lattice_.face(axis, v.lo[a]) - h)
      out.push_back({axis, v.lo[a], lattice_.face(axis, v.lo[a]), {none, whole}, 0.0});
    if (hi > lattice_.face(axis, v.hi[a] + 1) + h)
      out.push_back({axis, v.hi[a] + 1, lattice_.face(axis, v.hi[a] + 1), {whole, none}, 0.0});
  }
}

std::vector<Cut> CutSearch::candidates(const VoxelSet& voxels, const Box3& bounds) const {
  std::vector<Cut> out;
  const auto add = [&](const std::optional<Cut>& c) {
    if (!c) return;
    const auto same = [&](const Cut& o) {
      return o.axis == c->axis && o.coordinate == c->coordinate;
    };
    if (std::none_of(out.begin(), out.end(), same)) out.push_back(*c);
  };
  if (voxels.measure().count > 0) {
    add(choose(voxels));
    for (int axis = 0; axis < 3; ++axis) add(balanced(voxels, axis));
  }
  std::vector<Cut> trims;
  appendTrims(voxels, bounds, trims);
  for (const Cut& c : trims) add(c);
  return out;
}

std::vector<Cut> CutSearch::fallbacks(const VoxelSet& voxels) const {
  std::vector<Cut> out;
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<std::size_t>(axis);
    const std::vector<std::array<VoxelMeasure, 2>> cuts = voxels.cuts(axis);
    const int lo = voxels.box().lo[a], size = voxels.box().size(axis);
    for (int eighths : {1, 2, 6, 7}) {
      const std::optional<Cut> cut = at(voxels, cuts, axis, lo + (size * eighths + 4) / 8);
      if (cut && (out.empty() || out.back().axis != axis || out.back().at != cut->at))
        out.push_back(*cut);
    }
  }
  return out;
}

}  // namespace hfts::preprocess
