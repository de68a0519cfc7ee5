#pragma once
// Recursive partition of the contacts into the Hierarchical Fingertip
// Space (paper Sec. II-A).

#include <cstdint>
#include <vector>

#include "hfts_db/object_database.h"

namespace hfts::preprocess {

struct HierarchyOptions {
  std::vector<std::uint32_t> branching = {20, 4, 4};
  double length_scale = 0.05;  ///< positions are divided by this (m)
  double normal_weight = 0.5;  ///< unit normals are multiplied by this
  std::uint32_t iterations = 50;
  std::uint64_t seed = 1;
};

/// The partition, with the contacts reordered so that every node is a
/// contiguous range.
struct Hierarchy {
  std::vector<std::uint32_t> order;  ///< order[i] = input index of contact i
  std::vector<std::vector<db::HierarchyNode>> levels;
};

/// Partitions the contacts level by level: each node of level l is split
/// by k-means++ on [position / length_scale, normal * normal_weight] into
/// min(branching[l+1], size) children. A node with fewer contacts than the
/// branching factor thus gets one child per contact, and a single-contact
/// node a single child, so every leaf sits on the last level. Each node's
/// representative is the contact nearest to its mean position, its normal
/// the normalised mean normal (the representative's own normal if the mean
/// vanishes). Every node gets its own seed derived from `seed` and its
/// place in the tree. Throws std::invalid_argument on bad options.
Hierarchy buildHierarchy(const db::Points3& positions, const db::Points3& normals,
                         const HierarchyOptions& options);

}  // namespace hfts::preprocess
