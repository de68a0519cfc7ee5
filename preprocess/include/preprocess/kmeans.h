#pragma once
// Seeded k-means++ clustering, the partitioning step of the HFTS.

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace hfts::preprocess {

using Features = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Clusters the rows of `features` into exactly min(k, rows) non-empty
/// clusters: k-means++ seeding, then at most `iterations` Lloyd steps
/// (stopping early when no assignment changes). Clusters that fall empty
/// take the point farthest from its centre. Returns the cluster of each
/// row, numbered 0..k'-1 in order of first appearance in the input.
/// Deterministic for a given seed. Throws std::invalid_argument if k == 0.
std::vector<std::uint32_t> kmeansPlusPlus(const Features& features, std::uint32_t k,
                                          std::uint32_t iterations, std::uint64_t seed);

}  // namespace hfts::preprocess
