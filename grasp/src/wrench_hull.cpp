#include "wrench_hull.h"

#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/invalid_argument.h"

namespace hfts::grasp {
namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;
constexpr int kDim = 6;
// A ridge (kDim - 1 wrench indices) is keyed by one 64-bit word.
constexpr int kIndexBits = 12;
constexpr Eigen::Index kMaxWrenches = Eigen::Index{1} << kIndexBits;
static_assert((kDim - 1) * kIndexBits <= 64);

struct Facet {
  std::array<int, kDim> vertices{};    // wrench indices
  std::array<int, kDim> neighbours{};  // facet across the ridge without vertices[k]
  Vector6 normal = Vector6::Zero();    // unit, outward
  double offset = 0.0;                 // normal . x = offset on the plane
  bool alive = true;
  bool visible = false;
};

class Hull {
 public:
  /// Starts over on a new wrench set, keeping the buffers of earlier
  /// calls (no allocation in the common case).
  void reset(const Eigen::Matrix<double, 6, Eigen::Dynamic>& w) {
    w_ = &w;
    scale_ = std::max(1e-300, w.cwiseAbs().maxCoeff());
    eps_ = 1e-11 * scale_;
    facets_.clear();
    tested_.clear();
    stamp_ = 0;
  }

  /// Makes the first hull: the simplex of seven points spread wide, the
  /// first farthest from the centroid, each next the farthest from the
  /// affine span of those before. Returns false when the points do not
  /// span 6-D (the hull is flat).
  bool buildSimplex() {
    std::array<int, kDim + 1> simplex{};
    (w_->colwise() - w_->rowwise().mean()).colwise().squaredNorm().maxCoeff(&simplex[0]);
    // Gram-Schmidt on all points at once: each column of residual_ is a
    // point minus simplex[0], less its part in the directions chosen.
    residual_ = w_->colwise() - w_->col(simplex[0]);
    for (std::size_t k = 1; k <= kDim; ++k) {
      const double norm2 = residual_.colwise().squaredNorm().maxCoeff(&simplex[k]);
      if (!(norm2 > 1e-18 * scale_ * scale_)) return false;
      const Vector6 direction = residual_.col(simplex[k]) / std::sqrt(norm2);
      for (Eigen::Index i = 0; i < residual_.cols(); ++i)
        residual_.col(i) -= direction.dot(residual_.col(i)) * direction;
    }
    // Row k-1 of the inverse of the edge matrix is orthogonal to every edge
    // but edge k, and has product 1 with it: the normal of the facet
    // without simplex[k], pointing inwards. The sum of the rows is
    // orthogonal to the differences of edges and has product 1 with each:
    // the normal of the facet without simplex[0], pointing outwards.
    Eigen::Matrix<double, kDim, kDim> edges;
    for (int k = 1; k <= kDim; ++k)
      edges.col(k - 1) = w_->col(simplex[static_cast<std::size_t>(k)]) - w_->col(simplex[0]);
    const Eigen::Matrix<double, kDim, kDim> inverse = edges.inverse();
    for (int omit = 0; omit <= kDim; ++omit) {
      Facet f;
      int k = 0;
      for (int j = 0; j <= kDim; ++j) {
        if (j == omit) continue;
        f.vertices[static_cast<std::size_t>(k)] = simplex[static_cast<std::size_t>(j)];
        // Across the ridge without simplex[j] lies the facet omitting j.
        f.neighbours[static_cast<std::size_t>(k)] = j;
        ++k;
      }
      const Vector6 normal = omit == 0 ? Vector6(inverse.colwise().sum().transpose())
                                       : Vector6(-inverse.row(omit - 1).transpose());
      f.normal = normal.normalized();
      f.offset = f.normal.dot(w_->col(simplex[omit == 0 ? 1 : 0]));
      facets_.push_back(f);
    }
    return true;
  }

  /// Gives every point a facet it sees (its conflict), or -1 if it lies
  /// inside the initial simplex.
  void assignConflicts() {
    conflict_.assign(static_cast<std::size_t>(w_->cols()), -1);
    for (int i = 0; i < w_->cols(); ++i)
      for (int fi = 0; fi <= kDim && conflict_[static_cast<std::size_t>(i)] < 0; ++fi)
        if (sees(fi, i)) conflict_[static_cast<std::size_t>(i)] = fi;
  }

  /// Adds point p if it lies outside; false on a combinatorial inconsistency.
  bool insert(int p) {
    const int start = conflict_[static_cast<std::size_t>(p)];
    if (start < 0) return true;  // inside: the hull only grows, so for good
    ++stamp_;
    collectVisible(start, p);
    const Vector6 x = w_->col(p);
    const std::size_t firstNew = facets_.size();
    for (const int fi : visible_) {
      for (int k = 0; k < kDim; ++k) {
        const int ni =
            facets_[static_cast<std::size_t>(fi)].neighbours[static_cast<std::size_t>(k)];
        if (facets_[static_cast<std::size_t>(ni)].visible) continue;
        if (!addHorizonFacet(fi, k, ni, p, x)) return false;
      }
    }
    for (const int fi : visible_) {
      facets_[static_cast<std::size_t>(fi)].alive = false;
      facets_[static_cast<std::size_t>(fi)].visible = false;
    }
    if (!linkNewFacets(firstNew, p)) return false;
    reassignConflicts(firstNew, p);
    return true;
  }

  /// The depth of the origin, inserting only the points that can change
  /// it: while some pending point sees the facet nearest the origin (the
  /// one with the smallest offset), insert the highest of them. Once none
  /// does, that facet is on the final hull, so the depth is at most its
  /// offset; and it is at least that, since the hull only grows. The
  /// other points need not be inserted. nullopt on an inconsistency.
  std::optional<double> depth() {
    for (;;) {
      const int nearest = nearestFacet();
      const int p = highestOver(nearest);
      if (p < 0) {
        const double offset = facets_[static_cast<std::size_t>(nearest)].offset;
        return offset > eps_ ? offset : 0.0;
      }
      if (!insert(p)) return std::nullopt;
      if (facets_.size() > kMaxHullFacets)
        throw InvalidArgument("contacts", "the wrench hull of these contacts grew beyond " +
                                              std::to_string(kMaxHullFacets) +
                                              " facets; use fewer contacts or cone edges");
    }
  }

 private:
  /// Signed distance of a point above a facet's plane.
  double height(int fi, int point) const {
    const Facet& f = facets_[static_cast<std::size_t>(fi)];
    return f.normal.dot(w_->col(point)) - f.offset;
  }
  bool sees(int fi, int point) const { return height(fi, point) > eps_; }

  int nearestFacet() const {
    int nearest = -1;
    double offset = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < facets_.size(); ++i) {
      if (facets_[i].alive && facets_[i].offset < offset) {
        offset = facets_[i].offset;
        nearest = static_cast<int>(i);
      }
    }
    return nearest;
  }

  /// The pending point highest over facet fi among those that see it, -1
  /// if none does.
  int highestOver(int fi) const {
    int highest = -1;
    double top = eps_;
    for (std::size_t i = 0; i < conflict_.size(); ++i) {
      if (conflict_[i] < 0) continue;
      const double h = height(fi, static_cast<int>(i));
      if (h > top) {
        top = h;
        highest = static_cast<int>(i);
      }
    }
    return highest;
  }

  /// The facets p sees form a connected region around `start`: walk it
  /// over neighbours instead of testing every facet.
  void collectVisible(int start, int p) {
    visible_.clear();
    queue_.assign(1, start);
    tested_.resize(facets_.size(), 0);
    tested_[static_cast<std::size_t>(start)] = stamp_;
    while (!queue_.empty()) {
      const int fi = queue_.back();
      queue_.pop_back();
      Facet& f = facets_[static_cast<std::size_t>(fi)];
      f.visible = sees(fi, p);
      if (!f.visible) continue;
      visible_.push_back(fi);
      for (const int ni : f.neighbours) {
        if (tested_[static_cast<std::size_t>(ni)] == stamp_) continue;
        tested_[static_cast<std::size_t>(ni)] = stamp_;
        queue_.push_back(ni);
      }
    }
  }

  /// Points whose conflict facet was removed either see one of the new
  /// facets (which replace the removed region) or now lie inside.
  void reassignConflicts(std::size_t firstNew, int p) {
    conflict_[static_cast<std::size_t>(p)] = -1;
    for (std::size_t i = 0; i < conflict_.size(); ++i) {
      int& c = conflict_[i];
      if (c < 0 || facets_[static_cast<std::size_t>(c)].alive) continue;
      c = -1;
      for (std::size_t gi = firstNew; gi < facets_.size() && c < 0; ++gi)
        if (sees(static_cast<int>(gi), static_cast<int>(i))) c = static_cast<int>(gi);
    }
  }

  /// The facet on the horizon ridge of visible facet `fi` (without its
  /// vertex k) and point p. Its plane contains the ridge, so it is a
  /// combination of the planes of fi and of the hidden neighbour ni.
  bool addHorizonFacet(int fi, int k, int ni, int p, const Vector6& x) {
    Facet g;
    const Facet& f = facets_[static_cast<std::size_t>(fi)];
    const Facet& n = facets_[static_cast<std::size_t>(ni)];
    g.vertices = f.vertices;
    g.vertices[static_cast<std::size_t>(k)] = p;
    const double above = f.normal.dot(x) - f.offset;  // > 0: p sees f
    const double below = n.offset - n.normal.dot(x);  // >= 0: p does not see n
    Vector6 normal = below * f.normal + above * n.normal;
    double offset = below * f.offset + above * n.offset;
    const double length = normal.norm();
    if (!(length > 0.0)) return false;
    g.normal = normal / length;
    g.offset = offset / length;
    g.neighbours.fill(-1);
    g.neighbours[static_cast<std::size_t>(k)] = ni;
    const int gi = static_cast<int>(facets_.size());
    Facet& hidden = facets_[static_cast<std::size_t>(ni)];
    const auto it = std::find(hidden.neighbours.begin(), hidden.neighbours.end(), fi);
    if (it == hidden.neighbours.end()) return false;
    *it = gi;
    facets_.push_back(g);
    return true;
  }

  /// The keys of a facet's ridges (entry k: the ridge without vertices[k]),
  /// each naming the ridge's vertex set exactly: a bit mask for at most 64
  /// wrenches (the common, faster case), else the five indices in
  /// increasing order, kIndexBits each.
  std::array<std::uint64_t, kDim> ridgeKeys(const Facet& g) const {
    std::array<std::uint64_t, kDim> keys{};
    if (w_->cols() <= 64) {
      std::uint64_t all = 0;
      for (const int v : g.vertices) all |= std::uint64_t{1} << v;
      for (std::size_t k = 0; k < kDim; ++k) keys[k] = all & ~(std::uint64_t{1} << g.vertices[k]);
      return keys;
    }
    std::array<int, kDim> sorted = g.vertices;
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t k = 0; k < kDim; ++k)
      for (const int u : sorted)
        if (u != g.vertices[k]) keys[k] = (keys[k] << kIndexBits) | static_cast<std::uint64_t>(u);
    return keys;
  }

  /// New facets meet each other across ridges that contain p: pair them
  /// through a small open-addressing table keyed by the ridge's vertex set
  /// (ridgeKeys).
  bool linkNewFacets(std::size_t firstNew, int p) {
    const std::size_t ridges = (facets_.size() - firstNew) * (kDim - 1);
    if (table_.size() < 2 * ridges) {
      std::size_t capacity = 64;
      while (capacity < 2 * ridges) capacity *= 2;
      table_.assign(capacity, Slot{});
    }
    ++generation_;  // empties the table without touching it
    const std::size_t mask = table_.size() - 1;
    long unpaired = 0;
    for (std::size_t gi = firstNew; gi < facets_.size(); ++gi) {
      const Facet& g = facets_[gi];
      const std::array<std::uint64_t, kDim> keys = ridgeKeys(g);
      for (int k = 0; k < kDim; ++k) {
        if (g.vertices[static_cast<std::size_t>(k)] == p) continue;
        const std::uint64_t key = keys[static_cast<std::size_t>(k)];
        for (std::size_t h = (key * 0x9e3779b97f4a7c15ULL) >> 40;; ++h) {
          Slot& slot = table_[h & mask];
          if (slot.generation != generation_) {
            slot = {key, generation_, static_cast<int>(gi), k};
            ++unpaired;
            break;
          }
          if (slot.key == key) {
            if (slot.facet < 0) return false;  // a third facet on one ridge
            facets_[gi].neighbours[static_cast<std::size_t>(k)] = slot.facet;
            facets_[static_cast<std::size_t>(slot.facet)]
                .neighbours[static_cast<std::size_t>(slot.slot)] = static_cast<int>(gi);
            slot.facet = -1;
            --unpaired;
            break;
          }
        }
      }
    }
    return unpaired == 0;
  }

  struct Slot {
    std::uint64_t key = 0;
    std::uint64_t generation = 0;
    int facet = -1;
    int slot = -1;
  };
  std::vector<Slot> table_;
  std::uint64_t generation_ = 0;
  std::vector<int> visible_, queue_, conflict_;
  std::vector<std::uint64_t> tested_;
  std::uint64_t stamp_ = 0;

  const Eigen::Matrix<double, 6, Eigen::Dynamic>* w_ = nullptr;
  std::vector<Facet> facets_;
  Eigen::Matrix<double, 6, Eigen::Dynamic> residual_;  // buildSimplex's
  double scale_ = 1.0, eps_ = 0.0;
};

}  // namespace

std::optional<double> originDepthIncremental(const Eigen::Matrix<double, 6, Eigen::Dynamic>& w) {
  // One hull per thread, reused: its buffers outlive the call.
  thread_local Hull hull;
  hull.reset(w);
  if (w.cols() <= kDim || !hull.buildSimplex()) return 0.0;
  if (w.cols() > kMaxWrenches) return std::nullopt;  // ridge keys hold 12-bit indices
  hull.assignConflicts();
  return hull.depth();
}

}  // namespace hfts::grasp
