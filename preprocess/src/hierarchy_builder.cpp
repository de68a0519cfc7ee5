#include "preprocess/hierarchy_builder.h"

#include <cmath>
#include <numeric>
#include <stdexcept>

#include "preprocess/kmeans.h"

namespace hfts::preprocess {
namespace {

/// SplitMix64 finaliser: decorrelates the seeds of neighbouring nodes.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

using Members = std::vector<std::uint32_t>;

std::vector<Members> split(const Members& members, const Features& all, std::uint32_t k,
                           const HierarchyOptions& options, std::uint64_t nodeSeed) {
  Features x(static_cast<Eigen::Index>(members.size()), all.cols());
  for (std::size_t i = 0; i < members.size(); ++i)
    x.row(static_cast<Eigen::Index>(i)) = all.row(members[i]);
  const std::vector<std::uint32_t> label = kmeansPlusPlus(x, k, options.iterations, nodeSeed);
  std::vector<Members> children;
  for (std::size_t i = 0; i < members.size(); ++i) {
    if (label[i] >= children.size()) children.resize(label[i] + 1);
    children[label[i]].push_back(members[i]);
  }
  return children;
}

void setRepresentative(db::HierarchyNode& node, const db::Points3& positions,
                       const db::Points3& normals) {
  const Eigen::Index begin = node.contact_begin;
  const Eigen::Index count = node.contact_count;
  const Eigen::RowVector3d mean = positions.middleRows(begin, count).colwise().mean();
  Eigen::Index nearest = 0;
  (positions.middleRows(begin, count).rowwise() - mean).rowwise().squaredNorm().minCoeff(&nearest);
  node.representative = static_cast<std::uint32_t>(begin + nearest);
  const Eigen::Vector3d sum = normals.middleRows(begin, count).colwise().sum().transpose();
  node.mean_normal = sum.norm() > 1e-9 * static_cast<double>(count)
                         ? Eigen::Vector3d(sum.normalized())
                         : Eigen::Vector3d(normals.row(node.representative).transpose());
}

void checkOptions(const HierarchyOptions& options, Eigen::Index n) {
  if (options.branching.empty()) throw std::invalid_argument("branching needs at least one level");
  for (std::uint32_t b : options.branching)
    if (b == 0) throw std::invalid_argument("branching factors must be >= 1");
  if (!(options.length_scale > 0.0) || !std::isfinite(options.length_scale))
    throw std::invalid_argument("length scale must be positive");
  if (!(options.normal_weight >= 0.0) || !std::isfinite(options.normal_weight))
    throw std::invalid_argument("normal weight must be >= 0");
  if (n == 0) throw std::invalid_argument("no contacts to partition");
}

}  // namespace

Hierarchy buildHierarchy(const db::Points3& positions, const db::Points3& normals,
                         const HierarchyOptions& options) {
  checkOptions(options, positions.rows());
  Features features(positions.rows(), 6);
  features.leftCols(3) = positions / options.length_scale;
  features.rightCols(3) = normals * options.normal_weight;

  // Breadth-first: members[l][j] are the input indices of node j on level l.
  const std::size_t numLevels = options.branching.size();
  std::vector<std::vector<Members>> members(numLevels);
  std::vector<std::vector<std::uint32_t>> childCount(numLevels);
  Members all(static_cast<std::size_t>(positions.rows()));
  std::iota(all.begin(), all.end(), 0u);
  members[0] = split(all, features, options.branching[0], options, mix(options.seed));
  for (std::size_t l = 0; l + 1 < numLevels; ++l) {
    for (std::size_t j = 0; j < members[l].size(); ++j) {
      const std::uint64_t nodeSeed = mix(options.seed ^ mix((l + 1) << 32 | j));
      std::vector<Members> children =
          split(members[l][j], features, options.branching[l + 1], options, nodeSeed);
      childCount[l].push_back(static_cast<std::uint32_t>(children.size()));
      for (Members& child : children) members[l + 1].push_back(std::move(child));
    }
  }

  Hierarchy out;
  for (const Members& leaf : members.back())
    out.order.insert(out.order.end(), leaf.begin(), leaf.end());
  db::Points3 sortedPositions(positions.rows(), 3), sortedNormals(positions.rows(), 3);
  for (std::size_t i = 0; i < out.order.size(); ++i) {
    sortedPositions.row(static_cast<Eigen::Index>(i)) = positions.row(out.order[i]);
    sortedNormals.row(static_cast<Eigen::Index>(i)) = normals.row(out.order[i]);
  }
  // Children are contiguous in breadth-first order, so ranges follow from
  // cumulative sizes on every level.
  out.levels.resize(numLevels);
  for (std::size_t l = 0; l < numLevels; ++l) {
    std::uint32_t begin = 0, child = 0;
    for (std::size_t j = 0; j < members[l].size(); ++j) {
      db::HierarchyNode node;
      node.contact_begin = begin;
      node.contact_count = static_cast<std::uint32_t>(members[l][j].size());
      node.child_begin = child;
      node.child_count = l + 1 < numLevels ? childCount[l][j] : 0;
      setRepresentative(node, sortedPositions, sortedNormals);
      begin += node.contact_count;
      child += node.child_count;
      out.levels[l].push_back(node);
    }
  }
  return out;
}

}  // namespace hfts::preprocess
