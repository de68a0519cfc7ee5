#include "grasp/hfts_space.h"

#include <stdexcept>
#include <string>

#include "hfts_db/invalid_argument.h"

namespace hfts::grasp {

std::size_t HftsNodeHash::operator()(const HftsNode& n) const {
  std::uint64_t h = static_cast<std::uint64_t>(n.level) * 0x9e3779b97f4a7c15ULL;
  for (const std::uint32_t p : n.parts) h = (h ^ p) * 0x100000001b3ULL;
  return static_cast<std::size_t>(h ^ (h >> 29));
}

HftsSpace::HftsSpace(const db::ObjectDatabase& database, int fingers)
    : database_(database), fingers_(fingers) {
  if (fingers < 1 || fingers > kMaxFingers)
    throw InvalidArgument("fingers", "must be in 1.." + std::to_string(kMaxFingers) + ", got " +
                                         std::to_string(fingers));
  // parent_[l][p]: parent partition (in level l - 1) of partition p of level l.
  parent_.resize(database.levels.size() + 1);
  for (std::size_t l = 0; l + 1 < database.levels.size(); ++l) {
    parent_[l + 2].resize(database.levels[l + 1].size());
    for (std::uint32_t p = 0; p < database.levels[l].size(); ++p) {
      const db::HierarchyNode& node = database.levels[l][p];
      for (std::uint32_t c = node.child_begin; c < node.child_begin + node.child_count; ++c)
        parent_[l + 2][c] = p;
    }
  }
  // leaves_[l][p]: leaf partitions below partition p of level l, bottom-up.
  const std::size_t levels = database.levels.size();
  leaves_.resize(levels + 1);
  for (std::size_t l = levels; l >= 1; --l) {
    leaves_[l].assign(database.levels[l - 1].size(), 1.0);
    if (l == levels) continue;
    for (std::size_t p = 0; p < leaves_[l].size(); ++p) {
      const db::HierarchyNode& node = database.levels[l - 1][p];
      double sum = 0.0;
      for (std::uint32_t c = node.child_begin; c < node.child_begin + node.child_count; ++c)
        sum += leaves_[l + 1][c];
      leaves_[l][p] = sum;
    }
  }
}

double HftsSpace::numLeaves(const HftsNode& node) const {
  double count = 1.0;
  if (node.level == 0) {
    double perFinger = 0.0;
    for (const double n : leaves_[1]) perFinger += n;
    for (int f = 0; f < fingers_; ++f) count *= perFinger;
    return count;
  }
  for (int f = 0; f < fingers_; ++f)
    count *= leaves_[static_cast<std::size_t>(node.level)][node.parts[static_cast<std::size_t>(f)]];
  return count;
}

std::pair<std::uint32_t, std::uint32_t> HftsSpace::childRange(int level, std::uint32_t part) const {
  if (level == 0) return {0, static_cast<std::uint32_t>(database_.levels.front().size())};
  const db::HierarchyNode& node = database_.levels[static_cast<std::size_t>(level - 1)][part];
  return {node.child_begin, node.child_begin + node.child_count};
}

std::uint64_t HftsSpace::numChildren(const HftsNode& node) const {
  if (isLeaf(node)) return 0;
  std::uint64_t count = 1;
  for (int f = 0; f < fingers_; ++f) {
    const auto [begin, end] = childRange(node.level, node.parts[static_cast<std::size_t>(f)]);
    count *= end - begin;
  }
  return count;
}

HftsNode HftsSpace::child(const HftsNode& parent, std::uint64_t index) const {
  if (index >= numChildren(parent)) throw std::out_of_range("HftsSpace::child: no such child");
  HftsNode out;
  out.level = parent.level + 1;
  for (int f = 0; f < fingers_; ++f) {
    const auto [begin, end] = childRange(parent.level, parent.parts[static_cast<std::size_t>(f)]);
    out.parts[static_cast<std::size_t>(f)] =
        begin + static_cast<std::uint32_t>(index % (end - begin));
    index /= end - begin;
  }
  return out;
}

HftsNode HftsSpace::parent(const HftsNode& node) const {
  if (node.level == 0) throw std::invalid_argument("HftsSpace::parent: the root has none");
  HftsNode out;
  out.level = node.level - 1;
  if (out.level > 0)
    for (int f = 0; f < fingers_; ++f)
      out.parts[static_cast<std::size_t>(f)] =
          parent_[static_cast<std::size_t>(node.level)][node.parts[static_cast<std::size_t>(f)]];
  return out;
}

std::uint64_t HftsSpace::childIndex(const HftsNode& node) const {
  const HftsNode up = parent(node);
  std::uint64_t index = 0, radix = 1;
  for (int f = 0; f < fingers_; ++f) {
    const auto [begin, end] = childRange(up.level, up.parts[static_cast<std::size_t>(f)]);
    index += radix * (node.parts[static_cast<std::size_t>(f)] - begin);
    radix *= end - begin;
  }
  return index;
}

GraspContacts HftsSpace::representative(const HftsNode& node) const {
  if (node.level < 1 || node.level > numLevels())
    throw std::invalid_argument("HftsSpace::representative: the root has no grasp");
  GraspContacts g{Eigen::Matrix3Xd(3, fingers_), Eigen::Matrix3Xd(3, fingers_)};
  const auto& level = database_.levels[static_cast<std::size_t>(node.level - 1)];
  for (int f = 0; f < fingers_; ++f) {
    const db::HierarchyNode& part = level.at(node.parts[static_cast<std::size_t>(f)]);
    g.positions.col(f) = database_.positions.row(part.representative).transpose();
    g.outward_normals.col(f) = part.mean_normal;
  }
  return g;
}

}  // namespace hfts::grasp
