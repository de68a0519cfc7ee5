#pragma once
// The Hierarchical Fingertip Space of an object (paper Sec. II-A): a node
// on level l is an m-tuple of contact partitions of level l, one per
// finger; its children are all m-tuples of the partitions' children.

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <functional>

#include "hfts_db/object_database.h"

namespace hfts::grasp {

inline constexpr int kMaxFingers = 4;

/// A node of the HFTS. Level 0 is the root (no partitions); level l >= 1
/// holds one partition index of database level l (levels[l-1]) per finger.
struct HftsNode {
  int level = 0;
  std::array<std::uint32_t, kMaxFingers> parts{};

  bool operator==(const HftsNode& o) const { return level == o.level && parts == o.parts; }
};

struct HftsNodeHash {
  std::size_t operator()(const HftsNode& n) const;
};

/// Contacts of a grasp: one column per finger, object frame.
struct GraspContacts {
  Eigen::Matrix3Xd positions;
  Eigen::Matrix3Xd outward_normals;
};

/// The HFTS of one object database for an m-finger hand. The database must
/// outlive the space.
class HftsSpace {
 public:
  /// Throws std::invalid_argument unless 1 <= fingers <= kMaxFingers.
  HftsSpace(const db::ObjectDatabase& database, int fingers);

  int fingers() const { return fingers_; }
  int numLevels() const { return static_cast<int>(database_.levels.size()); }
  HftsNode root() const { return HftsNode{}; }
  bool isLeaf(const HftsNode& node) const { return node.level == numLevels(); }
  const db::ObjectDatabase& database() const { return database_; }

  /// Number of children: the product over fingers of the partitions'
  /// child counts (8000 for the root of a 20-4-4 space). 0 for leaves.
  std::uint64_t numChildren(const HftsNode& node) const;
  /// Child number `index` (0 <= index < numChildren) in mixed radix over
  /// the fingers' child partitions.
  HftsNode child(const HftsNode& parent, std::uint64_t index) const;
  /// The inverse of child(); the parent is implied by the child's partitions.
  std::uint64_t childIndex(const HftsNode& child) const;
  HftsNode parent(const HftsNode& node) const;
  /// Number of leaves in the branch rooted at `node` (1 for a leaf): the
  /// product over fingers of the leaf partitions below each partition.
  double numLeaves(const HftsNode& node) const;

  /// The node's representative grasp: per finger, the representative
  /// contact of its partition, with the partition's normalised mean
  /// (outward) normal. Root: throws std::invalid_argument.
  GraspContacts representative(const HftsNode& node) const;

 private:
  /// Children of partition `part` of `level` (0: the root) as a range of
  /// partitions of level + 1.
  std::pair<std::uint32_t, std::uint32_t> childRange(int level, std::uint32_t part) const;

  const db::ObjectDatabase& database_;
  int fingers_;
  std::vector<std::vector<std::uint32_t>> parent_;  // parent partition per level (1-based)
  std::vector<std::vector<double>> leaves_;         // leaf partitions below, per level (1-based)
};

}  // namespace hfts::grasp
