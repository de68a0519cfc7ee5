#include "grasp/hfts_space.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/invalid_argument.h"

namespace hfts::grasp {

std::size_t HftsNodeHash::operator()(const HftsNode& n) const {
  std::uint64_t h = static_cast<std::uint64_t>(n.level) * 0x9e3779b97f4a7c15ULL;
  for (const std::uint32_t p : n.parts) h = (h ^ p) * 0x100000001b3ULL;
  return static_cast<std::size_t>(h ^ (h >> 29));
}

HftsSpace::HftsSpace(const db::ObjectDatabase& database, int fingers,
                     const std::vector<bool>* usable)
    : database_(database), fingers_(fingers) {
  if (fingers < 1 || fingers > kMaxFingers)
    throw InvalidArgument("fingers", "must be in 1.." + std::to_string(kMaxFingers) + ", got " +
                                         std::to_string(fingers));
  if (usable != nullptr && usable->size() != database.numContacts())
    throw InvalidArgument("usable", std::to_string(database.numContacts()) +
                                        " flags expected (one per contact), got " +
                                        std::to_string(usable->size()));
  usableContacts_ =
      usable == nullptr
          ? database.numContacts()
          : static_cast<std::size_t>(std::count(usable->begin(), usable->end(), true));
  const std::size_t levels = database.levels.size();
  levels_.resize(levels + 1);
  levels_[0].resize(1);
  // Bottom-up: a partition is kept when it holds a usable contact; a
  // partition of an upper level keeps its kept children.
  std::vector<std::vector<bool>> kept(levels + 1);
  for (std::size_t l = levels; l >= 1; --l) {
    const std::vector<db::HierarchyNode>& nodes = database.levels[l - 1];
    levels_[l].resize(nodes.size());
    kept[l].assign(nodes.size(), false);
    for (std::uint32_t p = 0; p < nodes.size(); ++p) {
      Partition& part = levels_[l][p];
      const db::HierarchyNode& node = nodes[p];
      if (l == levels) {
        kept[l][p] = usable == nullptr ||
                     std::any_of(usable->begin() + node.contact_begin,
                                 usable->begin() + node.contact_begin + node.contact_count,
                                 [](bool u) { return u; });
        part.leaves = kept[l][p] ? 1.0 : 0.0;
      } else {
        for (std::uint32_t c = node.child_begin; c < node.child_begin + node.child_count; ++c) {
          if (!kept[l + 1][c]) continue;
          levels_[l + 1][c].slot = static_cast<std::uint32_t>(part.children.size());
          levels_[l + 1][c].parent = p;
          part.children.push_back(c);
          part.leaves += levels_[l + 1][c].leaves;
        }
        kept[l][p] = !part.children.empty();
      }
      if (!kept[l][p]) continue;
      part.position = database.positions.row(node.representative).transpose();
      part.normal = node.mean_normal;
      if (usable != nullptr) representWithUsableContacts(part, node, *usable);
    }
  }
  for (std::uint32_t p = 0; p < levels_[1].size(); ++p) {
    if (!kept[1][p]) continue;
    levels_[1][p].slot = static_cast<std::uint32_t>(levels_[0][0].children.size());
    levels_[0][0].children.push_back(p);
    levels_[0][0].leaves += levels_[1][p].leaves;
  }
}

void HftsSpace::representWithUsableContacts(Partition& out, const db::HierarchyNode& node,
                                            const std::vector<bool>& usable) const {
  const std::uint32_t end = node.contact_begin + node.contact_count;
  std::uint32_t count = 0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::Zero();
  for (std::uint32_t i = node.contact_begin; i < end; ++i) {
    if (!usable[i]) continue;
    ++count;
    mean += database_.positions.row(i).transpose();
    normal += database_.normals.row(i).transpose();
  }
  if (count == node.contact_count) return;  // all usable: the database's own
  mean /= static_cast<double>(count);
  double nearest = std::numeric_limits<double>::infinity();
  for (std::uint32_t i = node.contact_begin; i < end; ++i) {
    const double d = (database_.positions.row(i).transpose() - mean).squaredNorm();
    if (usable[i] && d < nearest) {
      nearest = d;
      out.position = database_.positions.row(i).transpose();
    }
  }
  if (normal.norm() > 1e-12) out.normal = normal.normalized();
}

double HftsSpace::numLeaves(const HftsNode& node) const {
  if (node.level == 0) return std::pow(partition(0, 0).leaves, fingers_);
  double count = 1.0;
  for (int f = 0; f < fingers_; ++f)
    count *= partition(node.level, node.parts[static_cast<std::size_t>(f)]).leaves;
  return count;
}

std::uint64_t HftsSpace::numChildren(const HftsNode& node) const {
  if (isLeaf(node)) return 0;
  std::uint64_t count = 1;
  for (int f = 0; f < fingers_; ++f) {
    const std::uint32_t part = node.level == 0 ? 0 : node.parts[static_cast<std::size_t>(f)];
    count *= partition(node.level, part).children.size();
  }
  return count;
}

HftsNode HftsSpace::child(const HftsNode& parent, std::uint64_t index) const {
  if (index >= numChildren(parent)) throw std::out_of_range("HftsSpace::child: no such child");
  HftsNode out;
  out.level = parent.level + 1;
  for (int f = 0; f < fingers_; ++f) {
    const std::uint32_t part = parent.level == 0 ? 0 : parent.parts[static_cast<std::size_t>(f)];
    const std::vector<std::uint32_t>& children = partition(parent.level, part).children;
    out.parts[static_cast<std::size_t>(f)] = children[index % children.size()];
    index /= children.size();
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
          partition(node.level, node.parts[static_cast<std::size_t>(f)]).parent;
  return out;
}

std::uint64_t HftsSpace::childIndex(const HftsNode& node) const {
  const HftsNode up = parent(node);
  std::uint64_t index = 0, radix = 1;
  for (int f = 0; f < fingers_; ++f) {
    const std::uint32_t part = up.level == 0 ? 0 : up.parts[static_cast<std::size_t>(f)];
    index += radix * partition(node.level, node.parts[static_cast<std::size_t>(f)]).slot;
    radix *= partition(up.level, part).children.size();
  }
  return index;
}

GraspContacts HftsSpace::representative(const HftsNode& node) const {
  if (node.level < 1 || node.level > numLevels())
    throw std::invalid_argument("HftsSpace::representative: the root has no grasp");
  GraspContacts g{Eigen::Matrix3Xd(3, fingers_), Eigen::Matrix3Xd(3, fingers_)};
  for (int f = 0; f < fingers_; ++f) {
    const Partition& part = partition(node.level, node.parts[static_cast<std::size_t>(f)]);
    g.positions.col(f) = part.position;
    g.outward_normals.col(f) = part.normal;
  }
  return g;
}

GraspContacts HftsSpace::leafContacts() const {
  const std::vector<Partition>& leaves = levels_.back();
  std::vector<const Partition*> usable;
  for (const Partition& p : leaves)
    if (p.leaves > 0.0) usable.push_back(&p);
  const auto n = static_cast<Eigen::Index>(usable.size());
  GraspContacts g{Eigen::Matrix3Xd(3, n), Eigen::Matrix3Xd(3, n)};
  for (Eigen::Index i = 0; i < n; ++i) {
    g.positions.col(i) = usable[static_cast<std::size_t>(i)]->position;
    g.outward_normals.col(i) = usable[static_cast<std::size_t>(i)]->normal;
  }
  return g;
}

}  // namespace hfts::grasp
