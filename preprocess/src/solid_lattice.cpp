#include "solid_lattice.h"

#include <algorithm>
#include <cmath>

namespace hfts::preprocess {
namespace {

/// Vertical lines through the points origin + spacing * (i, j, 0).
db::LineLattice verticalLines(const Eigen::Vector3d& origin, double spacing, int nx, int ny) {
  db::LineLattice lattice;
  lattice.axis = 2;
  lattice.origin = origin;
  lattice.spacing = spacing;
  lattice.counts = {static_cast<std::uint32_t>(nx), static_cast<std::uint32_t>(ny)};
  return lattice;
}

}  // namespace

SolidLattice::SolidLattice(const TriangleMesh& mesh, std::uint32_t resolution) : mesh_(mesh) {
  const Eigen::Vector3d lo = mesh.vertices.colwise().minCoeff().transpose();
  const Eigen::Vector3d hi = mesh.vertices.colwise().maxCoeff().transpose();
  spacing_ = (hi - lo).maxCoeff() / resolution;
  origin_ = lo.array() - 0.5 * spacing_;
  for (int c = 0; c < 3; ++c)
    count_[static_cast<std::size_t>(c)] =
        static_cast<int>(std::ceil((hi[c] - lo[c]) / spacing_)) + 2;
  centres_ = db::windingLines(mesh, verticalLines(origin_, spacing_, count_[0], count_[1]));
  columns_.resize(static_cast<std::size_t>(count_[0]) * static_cast<std::size_t>(count_[1]));
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    Eigen::Vector3d low = mesh.vertices.row(mesh.triangles(t, 0)).transpose(), high = low;
    for (int k = 1; k < 3; ++k) {
      low = low.cwiseMin(mesh.vertices.row(mesh.triangles(t, k)).transpose());
      high = high.cwiseMax(mesh.vertices.row(mesh.triangles(t, k)).transpose());
    }
    const std::array<int, 2> i = {column(0, low.x()), column(0, high.x())};
    const std::array<int, 2> j = {column(1, low.y()), column(1, high.y())};
    for (int y = j[0]; y <= j[1]; ++y)
      for (int x = i[0]; x <= i[1]; ++x)
        columns_[static_cast<std::size_t>(x) + static_cast<std::size_t>(count_[0]) * y].push_back(
            static_cast<std::uint32_t>(t));
  }
}

int SolidLattice::column(int axis, double x) const {
  // The voxel whose slab [face(i), face(i + 1)) holds x.
  const double i = std::floor((x - face(axis, 0)) / spacing_);
  return static_cast<int>(std::clamp(i, 0.0, count_[static_cast<std::size_t>(axis)] - 1.0));
}

VoxelBox SolidLattice::whole() const {
  return {{0, 0, 0}, {count_[0] - 1, count_[1] - 1, count_[2] - 1}};
}

void SolidLattice::runs(int i, int j, int k0, int k1, std::vector<LevelRun>& out) const {
  out.clear();
  const std::size_t line =
      centres_.lattice.index(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j));
  for (const db::Interval* s = centres_.begin(line); s != centres_.end(line); ++s) {
    // Level k is inside when enter < centre(k) <= exit; the estimate from
    // the division is corrected against those very comparisons.
    int first = std::max(k0, static_cast<int>(std::floor((s->enter - origin_.z()) / spacing_)));
    while (first <= k1 && !(centre(2, first) > s->enter)) ++first;
    while (first > k0 && centre(2, first - 1) > s->enter) --first;
    int last =
        std::min(k1, static_cast<int>(std::min((s->exit - origin_.z()) / spacing_ + 1.0, 1e9)));
    while (last >= first && !(centre(2, last) <= s->exit)) --last;
    if (first <= last) out.push_back({first, last});
  }
}

double SolidLattice::volumeIn(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const {
  const auto overlap = [&](int axis, int i) {
    return std::max(0.0, std::min(hi[axis], face(axis, i + 1)) - std::max(lo[axis], face(axis, i)));
  };
  double sum = 0.0;
  for (int j = std::max(0, column(1, lo.y())); j <= column(1, hi.y()); ++j) {
    const double wy = overlap(1, j);
    for (int i = std::max(0, column(0, lo.x())); i <= column(0, hi.x()); ++i) {
      const double w = overlap(0, i) * wy;
      if (w > 0.0)
        sum += w * centres_.length(centres_.lattice.index(static_cast<std::uint32_t>(i),
                                                          static_cast<std::uint32_t>(j)),
                                   lo.z(), hi.z());
    }
  }
  return sum;
}

bool SolidLattice::contains(const Eigen::Vector3d& p) const {
  // A triangle whose projection reaches p has p within its box, so it is
  // listed in p's column (column() is monotonic in x and y).
  const std::vector<std::uint32_t>& near =
      columns_[static_cast<std::size_t>(column(0, p.x())) +
               static_cast<std::size_t>(count_[0]) * static_cast<std::size_t>(column(1, p.y()))];
  TriangleMesh part;
  part.vertices.resize(static_cast<Eigen::Index>(3 * near.size()), 3);
  part.triangles.resize(static_cast<Eigen::Index>(near.size()), 3);
  for (std::size_t t = 0; t < near.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const auto row = static_cast<Eigen::Index>(3 * t) + k;
      part.vertices.row(row) = mesh_.vertices.row(mesh_.triangles(near[t], k));
      part.triangles(static_cast<Eigen::Index>(t), k) = static_cast<std::uint32_t>(row);
    }
  return db::windingLines(part, verticalLines(p, 1.0, 1, 1)).inside(0, p.z());
}

double solidVolume(const TriangleMesh& mesh) {
  constexpr double kLines = 256.0;  // along the longest side
  const Eigen::Vector3d lo = mesh.vertices.colwise().minCoeff().transpose();
  const Eigen::Vector3d hi = mesh.vertices.colwise().maxCoeff().transpose();
  const double spacing = (hi - lo).maxCoeff() / kLines;
  const int nx = static_cast<int>(std::ceil((hi.x() - lo.x()) / spacing)) + 1;
  const int ny = static_cast<int>(std::ceil((hi.y() - lo.y()) / spacing)) + 1;
  const Eigen::Vector3d origin = lo.array() + 0.5 * spacing;
  const db::WindingLines lines = db::windingLines(mesh, verticalLines(origin, spacing, nx, ny));
  double overlap = 0.0;
  for (double o : lines.overlap) overlap += o;
  return solidProperties(mesh).volume - overlap * spacing * spacing;
}

}  // namespace hfts::preprocess
