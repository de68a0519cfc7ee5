#pragma once
// The Hierarchical Fingertip Space of an object (paper Sec. II-A): a node
// on level l is an m-tuple of contact partitions of level l, one per
// finger; its children are all m-tuples of the partitions' children.

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

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

/// The HFTS of one object database for an m-finger hand, optionally
/// restricted to the contacts a placement leaves usable (contact_mask.h):
/// a partition without a usable contact is then no node's partition, so no
/// node that needs it is ever proposed, and a partition's representative
/// grasp uses its usable contacts only.
class HftsSpace {
 public:
  /// `usable` (may be null: every contact) holds one flag per contact of
  /// the database. The database must outlive the space. Throws
  /// InvalidArgument unless 1 <= fingers <= kMaxFingers and `usable` has
  /// one flag per contact.
  HftsSpace(const db::ObjectDatabase& database, int fingers,
            const std::vector<bool>* usable = nullptr);

  int fingers() const { return fingers_; }
  int numLevels() const { return static_cast<int>(database_.levels.size()); }
  HftsNode root() const { return HftsNode{}; }
  bool isLeaf(const HftsNode& node) const { return node.level == numLevels(); }
  const db::ObjectDatabase& database() const { return database_; }
  /// Contacts usable at all (all of them without a mask).
  std::size_t usableContacts() const { return usableContacts_; }

  /// Number of children: the product over fingers of the partitions'
  /// usable child counts (8000 for the root of a full 20-4-4 space). 0 for
  /// leaves, and for the root when no contact is usable.
  std::uint64_t numChildren(const HftsNode& node) const;
  /// Child number `index` (0 <= index < numChildren) in mixed radix over
  /// the fingers' usable child partitions.
  HftsNode child(const HftsNode& parent, std::uint64_t index) const;
  /// The inverse of child(); the parent is implied by the child's partitions.
  std::uint64_t childIndex(const HftsNode& child) const;
  HftsNode parent(const HftsNode& node) const;
  /// Number of leaves in the branch rooted at `node` (1 for a leaf): the
  /// product over fingers of the usable leaf partitions below each partition.
  double numLeaves(const HftsNode& node) const;

  /// The node's representative grasp: per finger, the representative
  /// contact of its partition (the usable contact nearest to the mean of
  /// the usable ones; the database's own when all are usable), with the
  /// normalised mean (outward) normal of those contacts. Root: throws
  /// std::invalid_argument.
  GraspContacts representative(const HftsNode& node) const;

  /// Every usable leaf partition's representative contact, one column
  /// each (all the contacts any leaf grasp of the space can use).
  GraspContacts leafContacts() const;

 private:
  /// Per partition of a level (level 0: the root, one partition).
  struct Partition {
    std::vector<std::uint32_t> children;  ///< usable partitions of the next level
    std::uint32_t slot = 0;               ///< index among its parent's children
    std::uint32_t parent = 0;             ///< partition of the level above
    double leaves = 0.0;                  ///< usable leaf partitions below (1 for a leaf)
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< representative contact
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();   ///< mean outward normal
  };
  const Partition& partition(int level, std::uint32_t part) const {
    return levels_[static_cast<std::size_t>(level)][part];
  }
  void representWithUsableContacts(Partition& out, const db::HierarchyNode& node,
                                   const std::vector<bool>& usable) const;

  const db::ObjectDatabase& database_;
  int fingers_;
  std::size_t usableContacts_ = 0;
  std::vector<std::vector<Partition>> levels_;  // [0]: the root; [l]: database level l - 1
};

}  // namespace hfts::grasp
