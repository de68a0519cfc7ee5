#include "preprocess/kmeans.h"

#include <algorithm>
#include <limits>
#include <random>
#include <stdexcept>

namespace hfts::preprocess {
namespace {

using Centers = Features;

Centers seedCenters(const Features& x, std::uint32_t k, std::mt19937_64& rng) {
  const Eigen::Index n = x.rows();
  Centers centers(k, x.cols());
  std::uniform_int_distribution<Eigen::Index> first(0, n - 1);
  centers.row(0) = x.row(first(rng));
  Eigen::VectorXd d2 = (x.rowwise() - centers.row(0)).rowwise().squaredNorm();
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (std::uint32_t c = 1; c < k; ++c) {
    const double total = d2.sum();
    Eigen::Index pick = 0;
    if (total > 0.0) {
      // D^2 weighting: the next centre is drawn proportional to the squared
      // distance to the nearest centre chosen so far.
      double u = uniform(rng) * total;
      while (pick < n - 1 && (u -= d2(pick)) > 0.0) ++pick;
    } else {
      pick = static_cast<Eigen::Index>(c) % n;  // all points coincide
    }
    centers.row(c) = x.row(pick);
    d2 = d2.cwiseMin((x.rowwise() - centers.row(c)).rowwise().squaredNorm());
  }
  return centers;
}

/// Assigns each row to its nearest centre; returns whether anything moved.
bool assign(const Features& x, const Centers& centers, std::vector<std::uint32_t>& label) {
  bool changed = false;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    Eigen::Index best = 0;
    (centers.rowwise() - x.row(i)).rowwise().squaredNorm().minCoeff(&best);
    const auto b = static_cast<std::uint32_t>(best);
    if (label[static_cast<std::size_t>(i)] != b) changed = true;
    label[static_cast<std::size_t>(i)] = b;
  }
  return changed;
}

void updateCenters(const Features& x, const std::vector<std::uint32_t>& label, Centers& centers) {
  Centers sums = Centers::Zero(centers.rows(), centers.cols());
  Eigen::VectorXd counts = Eigen::VectorXd::Zero(centers.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    sums.row(label[static_cast<std::size_t>(i)]) += x.row(i);
    counts(label[static_cast<std::size_t>(i)]) += 1.0;
  }
  for (Eigen::Index c = 0; c < centers.rows(); ++c)
    if (counts(c) > 0.0) centers.row(c) = sums.row(c) / counts(c);
}

/// Moves the point farthest from its centre (in a cluster of two or more)
/// into each empty cluster, so every cluster ends non-empty.
void fillEmptyClusters(const Features& x, const Centers& centers,
                       std::vector<std::uint32_t>& label) {
  std::vector<std::size_t> size(static_cast<std::size_t>(centers.rows()), 0);
  for (std::uint32_t l : label) ++size[l];
  for (std::size_t c = 0; c < size.size(); ++c) {
    if (size[c] > 0) continue;
    double worst = -1.0;
    std::size_t donor = 0;
    for (std::size_t i = 0; i < label.size(); ++i) {
      if (size[label[i]] < 2) continue;
      const double d = (x.row(static_cast<Eigen::Index>(i)) - centers.row(label[i])).squaredNorm();
      if (d > worst) {
        worst = d;
        donor = i;
      }
    }
    --size[label[donor]];
    label[donor] = static_cast<std::uint32_t>(c);
    size[c] = 1;
  }
}

/// Renumbers clusters in order of first appearance.
void canonicalize(std::vector<std::uint32_t>& label, std::uint32_t k) {
  std::vector<std::uint32_t> rename(k, std::numeric_limits<std::uint32_t>::max());
  std::uint32_t next = 0;
  for (std::uint32_t& l : label) {
    if (rename[l] == std::numeric_limits<std::uint32_t>::max()) rename[l] = next++;
    l = rename[l];
  }
}

}  // namespace

std::vector<std::uint32_t> kmeansPlusPlus(const Features& features, std::uint32_t k,
                                          std::uint32_t iterations, std::uint64_t seed) {
  if (k == 0) throw std::invalid_argument("k-means needs k >= 1");
  const auto n = static_cast<std::size_t>(features.rows());
  if (n == 0) return {};
  k = static_cast<std::uint32_t>(std::min<std::size_t>(k, n));
  std::vector<std::uint32_t> label(n, 0);
  if (k == 1) return label;

  std::mt19937_64 rng(seed);
  Centers centers = seedCenters(features, k, rng);
  assign(features, centers, label);
  for (std::uint32_t it = 0; it < iterations; ++it) {
    updateCenters(features, label, centers);
    if (!assign(features, centers, label)) break;
  }
  fillEmptyClusters(features, centers, label);
  canonicalize(label, k);
  return label;
}

}  // namespace hfts::preprocess
