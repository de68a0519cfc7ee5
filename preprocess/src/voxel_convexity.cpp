#include "voxel_convexity.h"

#include <algorithm>
#include <limits>
#include <numeric>

namespace hfts::preprocess {
namespace {

constexpr std::array<int, 2> kNone{1, 0};  // an empty extent: min > max

/// The convex hull of lattice points added column by column (strictly
/// increasing x, each column the points (x, a..b)), and the number of
/// lattice points in it (Pick: interior + boundary = (2A + B) / 2 + 1),
/// kept up to date in O(1) amortised per column by Andrew's monotone chain.
/// All integers: exact and deterministic.
class ChainHull {
 public:
  void add(int x, int a, int b) {
    if (upper_.empty()) first_ = b - a;
    push(upper_, x, b, true);
    push(lower_, x, a, false);
    last_ = b - a;
  }

  void clear() {
    upper_.clear();
    lower_.clear();
  }

  std::int64_t points() const {
    if (upper_.empty()) return 0;
    const std::int64_t area2 = upper_.back().area2 - lower_.back().area2;
    const std::int64_t boundary = upper_.back().boundary + lower_.back().boundary + first_ + last_;
    return (area2 + boundary) / 2 + 1;
  }

 private:
  struct Node {
    std::int64_t x, y;
    std::int64_t area2;     ///< twice the area under the chain from its first node
    std::int64_t boundary;  ///< lattice points on the chain, its first node excluded
  };

  static std::int64_t cross(const Node& o, const Node& a, std::int64_t x, std::int64_t y) {
    return (a.x - o.x) * (y - o.y) - (a.y - o.y) * (x - o.x);
  }

  /// Upper chain: right turns only; lower chain: left turns only.
  static void push(std::vector<Node>& chain, std::int64_t x, std::int64_t y, bool upper) {
    while (chain.size() >= 2) {
      const std::int64_t turn = cross(chain[chain.size() - 2], chain.back(), x, y);
      if (upper ? turn < 0 : turn > 0) break;
      chain.pop_back();
    }
    if (chain.empty()) {
      chain.push_back({x, y, 0, 0});
      return;
    }
    const Node& p = chain.back();
    chain.push_back({x, y, p.area2 + (x - p.x) * (y + p.y),
                     p.boundary + std::gcd(x - p.x, y >= p.y ? y - p.y : p.y - y)});
  }

  std::vector<Node> upper_, lower_;
  std::int64_t first_ = 0, last_ = 0;  ///< lengths of the first and last columns
};

void widen(std::array<int, 2>& e, int v) {
  e[0] = std::min(e[0], v);
  e[1] = std::max(e[1], v);
}

int third(int a, int b) {
  return 3 - a - b;
}

}  // namespace

VoxelSet::VoxelSet(const SolidLattice& lattice, const VoxelBox& box) {
  for (int c = 0; c < 3; ++c) n_[static_cast<std::size_t>(c)] = std::max(0, box.size(c));
  const int nx = n_[0], ny = n_[1], nz = n_[2];
  const std::array<int, 2> none{std::numeric_limits<int>::max(), std::numeric_limits<int>::min()};
  xOfZY_.assign(static_cast<std::size_t>(nz) * ny, none);
  yOfZX_.assign(static_cast<std::size_t>(nz) * nx, none);
  zOfXY_.assign(static_cast<std::size_t>(nx) * ny, none);
  for (int c = 0; c < 3; ++c)
    counts_[static_cast<std::size_t>(c)].assign(n_[static_cast<std::size_t>(c)], 0);
  std::vector<LevelRun> runs;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      lattice.runs(box.lo[0] + i, box.lo[1] + j, box.lo[2], box.hi[2], runs);
      for (const LevelRun& r : runs) {
        const int k0 = r.first - box.lo[2], k1 = r.last - box.lo[2];
        widen(zOfXY_[static_cast<std::size_t>(j) * nx + i], k0);
        widen(zOfXY_[static_cast<std::size_t>(j) * nx + i], k1);
        counts_[0][static_cast<std::size_t>(i)] += k1 - k0 + 1;
        counts_[1][static_cast<std::size_t>(j)] += k1 - k0 + 1;
        for (int k = k0; k <= k1; ++k) {
          widen(xOfZY_[static_cast<std::size_t>(k) * ny + j], i);
          widen(yOfZX_[static_cast<std::size_t>(k) * nx + i], j);
          ++counts_[2][static_cast<std::size_t>(k)];
        }
      }
    }
  frame_ = box;
  box_ = box;
  for (std::size_t c = 0; c < 3; ++c) {  // shrink to the solid voxels
    const std::vector<std::int64_t>& n = counts_[c];
    const auto first = std::find_if(n.begin(), n.end(), [](std::int64_t v) { return v > 0; });
    const auto last = std::find_if(n.rbegin(), n.rend(), [](std::int64_t v) { return v > 0; });
    box_.lo[c] = box.lo[c] + static_cast<int>(first - n.begin());
    box_.hi[c] = box.hi[c] - static_cast<int>(last - n.rbegin());
  }
  measure_ = measureAll();
}

std::array<int, 2> VoxelSet::extent(int slabAxis, int sweepAxis, int s, int t) const {
  const auto at = [](const std::vector<std::array<int, 2>>& table, int row, int width, int col) {
    const std::array<int, 2>& e = table[static_cast<std::size_t>(row) * width + col];
    return e[0] <= e[1] ? e : kNone;
  };
  const int nx = n_[0], ny = n_[1];
  switch (slabAxis * 3 + sweepAxis) {
    case 2 * 3 + 0:
      return at(yOfZX_, s, nx, t);  // slab k, sweep i
    case 2 * 3 + 1:
      return at(xOfZY_, s, ny, t);  // slab k, sweep j
    case 0 * 3 + 1:
      return at(zOfXY_, t, nx, s);  // slab i, sweep j
    case 0 * 3 + 2:
      return at(yOfZX_, t, nx, s);  // slab i, sweep k
    case 1 * 3 + 0:
      return at(zOfXY_, s, nx, t);  // slab j, sweep i
    default:
      return at(xOfZY_, t, ny, s);  // slab j, sweep k
  }
}

std::vector<std::int64_t> VoxelSet::sweep(int slabAxis, int sweepAxis, bool reverse) const {
  const int slabs = n_[static_cast<std::size_t>(slabAxis)];
  const int length = n_[static_cast<std::size_t>(sweepAxis)];
  std::vector<std::int64_t> out(static_cast<std::size_t>(length), 0);
  ChainHull hull;
  for (int s = 0; s < slabs; ++s) {
    hull.clear();
    for (int step = 0; step < length; ++step) {
      const int t = reverse ? length - 1 - step : step;
      const std::array<int, 2> e = extent(slabAxis, sweepAxis, s, t);
      if (e[0] <= e[1]) hull.add(reverse ? -t : t, e[0], e[1]);
      out[static_cast<std::size_t>(t)] += hull.points();
    }
  }
  return out;
}

VoxelMeasure VoxelSet::measureAll() const {
  VoxelMeasure m;
  for (std::int64_t c : counts_[0]) m.count += c;
  if (m.count == 0) return m;
  for (int d = 0; d < 3; ++d) {
    const int along = (d + 1) % 3;
    const std::vector<std::int64_t> hull = sweep(d, along, false);
    m.excess = std::max(m.excess, hull.back() - m.count);
  }
  return m;
}

std::vector<std::array<VoxelMeasure, 2>> VoxelSet::cuts(int axis) const {
  const auto c = static_cast<std::size_t>(axis);
  const int length = n_[c];
  std::vector<std::array<VoxelMeasure, 2>> out(static_cast<std::size_t>(std::max(0, length - 1)));
  if (out.empty()) return out;
  // Slabs across the cut's axis fall wholly on one side: their hulls add.
  const int other = (axis + 1) % 3;
  std::vector<std::int64_t> across(static_cast<std::size_t>(length), 0);
  ChainHull slab;
  for (int t = 0; t < length; ++t) {
    slab.clear();
    for (int u = 0; u < n_[static_cast<std::size_t>(third(axis, other))]; ++u) {
      const std::array<int, 2> e = extent(axis, third(axis, other), t, u);
      if (e[0] <= e[1]) slab.add(u, e[0], e[1]);
    }
    across[static_cast<std::size_t>(t)] = slab.points();
  }
  const std::array<std::vector<std::int64_t>, 2> below = {sweep(other, axis, false),
                                                          sweep(third(axis, other), axis, false)};
  const std::array<std::vector<std::int64_t>, 2> above = {sweep(other, axis, true),
                                                          sweep(third(axis, other), axis, true)};
  std::int64_t count = 0, hull = 0, total = 0, totalHull = 0;
  for (std::size_t t = 0; t < static_cast<std::size_t>(length); ++t) {
    total += counts_[c][t];
    totalHull += across[t];
  }
  for (std::size_t m = 1; m < static_cast<std::size_t>(length); ++m) {
    count += counts_[c][m - 1];
    hull += across[m - 1];
    VoxelMeasure& lo = out[m - 1][0];
    VoxelMeasure& hi = out[m - 1][1];
    lo.count = count;
    hi.count = total - count;
    lo.excess = std::max({hull, below[0][m - 1], below[1][m - 1]}) - lo.count;
    hi.excess = std::max({totalHull - hull, above[0][m], above[1][m]}) - hi.count;
  }
  return out;
}

}  // namespace hfts::preprocess
