#include "robot/pair_maps.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "robot/link_spheres.h"

namespace hfts::robot {
namespace {

/// Added to each DoF's half cell: covers the rounding of the kernels'
/// single-precision lookup (well under 1e-5 rad).
constexpr double kLookupMargin = 1e-4;

/// The link above `link`, -1 for the root.
int parentLink(const RobotModel& model, int link) {
  const int joint = model.links()[static_cast<std::size_t>(link)].parent_joint;
  return joint < 0 ? -1 : model.joints()[static_cast<std::size_t>(joint)].parent_link;
}

/// The joints from `link` up to (not including) `ancestor`, bottom up.
std::vector<int> jointsUpTo(const RobotModel& model, int link, int ancestor) {
  std::vector<int> out;
  for (; link != ancestor; link = parentLink(model, link))
    out.push_back(model.links()[static_cast<std::size_t>(link)].parent_joint);
  return out;
}

int commonAncestor(const RobotModel& model, int a, int b) {
  std::vector<bool> aboveA(model.links().size(), false);
  for (int l = a; l >= 0; l = parentLink(model, l)) aboveA[static_cast<std::size_t>(l)] = true;
  for (int l = b; l >= 0; l = parentLink(model, l))
    if (aboveA[static_cast<std::size_t>(l)]) return l;
  return -1;
}

/// One link of a pair: the joints between it and the pair's common
/// ancestor, and at a region's centre its nodes' centres in the ancestor's
/// frame with how far each node's points can move within the region
/// (computed for the nodes a descent meets).
class Side {
 public:
  Side(const RobotModel& model, const LinkSpheres& spheres, const std::vector<int>& joints)
      : spheres_(spheres),
        stamp_(spheres.tree.size(), 0),
        centres_(spheres.tree.size()),
        reach_(spheres.tree.size()) {
    for (const int j : joints) {
      const Joint& joint = model.joints()[static_cast<std::size_t>(j)];
      joints_.push_back(&joint);
      axes_.push_back(joint.axis.normalized());
    }
    toChild_.resize(joints_.size());
    turn_.resize(joints_.size());
  }

  /// Places the link at DoF values `value` (of dofs[0 ..]), each free to
  /// move by `halfWidth` around it.
  void place(const double* value, const double* halfWidth, const int* dofs) {
    ++generation_;
    // toChild_[k]: link frame -> the child frame of joints_[k] (bottom up).
    Eigen::Isometry3d below = Eigen::Isometry3d::Identity();
    for (std::size_t k = 0; k < joints_.size(); ++k) {
      const Joint& joint = *joints_[k];
      toChild_[k] = below;
      double v = 0.0;
      turn_[k] = 0.0;
      if (joint.type == Joint::Type::kRevolute) {
        const int slot = joint.dof == dofs[0] ? 0 : joint.dof == dofs[1] ? 1 : 2;
        v = joint.multiplier * value[slot] + joint.offset;
        turn_[k] = std::abs(joint.multiplier) * halfWidth[slot];
      }
      Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
      step.linear() = joint.rotation_fixed + std::cos(v) * joint.rotation_cos +
                      std::sin(v) * joint.rotation_sin;
      step.translation() = joint.origin.translation();
      below = step * below;
    }
    toAncestor_ = below;
  }

  /// The node's centre in the ancestor's frame.
  const Eigen::Vector3d& centre(int node) {
    update(node);
    return centres_[static_cast<std::size_t>(node)];
  }
  /// The node's radius plus how far its points can move: the turn of each
  /// joint times the distance from its axis, summed.
  double reach(int node) {
    update(node);
    return reach_[static_cast<std::size_t>(node)];
  }
  const SphereNode& node(int index) const { return spheres_.tree[static_cast<std::size_t>(index)]; }
  int root() const { return spheres_.root; }

 private:
  void update(int node) {
    const auto n = static_cast<std::size_t>(node);
    if (stamp_[n] == generation_) return;
    stamp_[n] = generation_;
    const LinkSphere& s = spheres_.tree[n].sphere;
    double reach = s.radius;
    for (std::size_t k = 0; k < joints_.size(); ++k) {
      if (turn_[k] == 0.0) continue;
      const Eigen::Vector3d x = toChild_[k] * s.center;
      reach += turn_[k] * ((x - x.dot(axes_[k]) * axes_[k]).norm() + s.radius);
    }
    centres_[n] = toAncestor_ * s.center;
    reach_[n] = reach;
  }

  const LinkSpheres& spheres_;
  std::vector<const Joint*> joints_;
  std::vector<Eigen::Vector3d> axes_;
  std::vector<Eigen::Isometry3d> toChild_;
  std::vector<double> turn_;
  Eigen::Isometry3d toAncestor_ = Eigen::Isometry3d::Identity();
  std::uint64_t generation_ = 0;
  std::vector<std::uint64_t> stamp_;
  std::vector<Eigen::Vector3d> centres_;
  std::vector<double> reach_;
};

/// The geometry the spheres of a cover farther than `clearance` from that of
/// b, both as placed (a node holds the geometry of the leaves below it);
/// `stack` is scratch.
bool placedApart(Side& a, Side& b, double clearance, std::vector<std::pair<int, int>>& stack) {
  stack.assign(1, {a.root(), b.root()});
  while (!stack.empty()) {
    const auto [na, nb] = stack.back();
    stack.pop_back();
    const double gap = (a.centre(na) - b.centre(nb)).norm() - a.reach(na) - b.reach(nb);
    if (gap > clearance) continue;
    const SphereNode& sa = a.node(na);
    const SphereNode& sb = b.node(nb);
    if (sa.leaf() && sb.leaf()) return false;
    if (!sa.leaf() && (sb.leaf() || a.reach(na) >= b.reach(nb))) {
      stack.emplace_back(sa.left, nb);
      stack.emplace_back(sa.right, nb);
    } else {
      stack.emplace_back(na, sb.left);
      stack.emplace_back(na, sb.right);
    }
  }
  return true;
}

class MapBuilder {
 public:
  MapBuilder(PairMap& map, Side& a, Side& b, double clearance)
      : map_(map), a_(a), b_(b), clearance_(clearance) {}

  /// Sets the cells of the block [lo[k], hi[k]) (k over the map's DoFs)
  /// proven apart, the whole block at once when it can be.
  void fill(const std::array<int, PairMap::kMaxDofs>& lo,
            const std::array<int, PairMap::kMaxDofs>& hi) {
    double value[PairMap::kMaxDofs], half[PairMap::kMaxDofs];
    for (int k = 0; k < PairMap::kMaxDofs; ++k) {
      value[k] = map_.lower[k] + 0.5 * (lo[k] + hi[k]) * map_.width[k];
      half[k] = 0.5 * (hi[k] - lo[k]) * map_.width[k] + kLookupMargin;
    }
    a_.place(value, half, map_.dofs);
    b_.place(value, half, map_.dofs);
    if (placedApart(a_, b_, clearance_, stack_)) {
      for (int i2 = lo[2]; i2 < hi[2]; ++i2)
        for (int i1 = lo[1]; i1 < hi[1]; ++i1)
          for (int i0 = lo[0]; i0 < hi[0]; ++i0) {
            const auto bit =
                static_cast<std::size_t>(i0 + map_.cells[0] * (i1 + map_.cells[1] * i2));
            map_.apart[bit / 32] |= std::uint32_t{1} << (bit % 32);
          }
      return;
    }
    // Split the block's longest side (in cells); a single cell stays unset.
    int longest = 0;
    for (int k = 1; k < PairMap::kMaxDofs; ++k)
      if (hi[k] - lo[k] > hi[longest] - lo[longest]) longest = k;
    if (hi[longest] - lo[longest] == 1) return;
    const int mid = (lo[longest] + hi[longest]) / 2;
    std::array<int, PairMap::kMaxDofs> split = hi;
    split[static_cast<std::size_t>(longest)] = mid;
    fill(lo, split);
    split = lo;
    split[static_cast<std::size_t>(longest)] = mid;
    fill(split, hi);
  }

 private:
  PairMap& map_;
  Side& a_;
  Side& b_;
  double clearance_;
  std::vector<std::pair<int, int>> stack_;  // scratch of placedApart
};

}  // namespace

bool PairMap::provesApart(const Eigen::VectorXd& q) const {
  int index = 0, stride = 1;
  for (int d = 0; d < kMaxDofs; ++d) {
    if (dofs[d] < 0) break;
    const double t = (q(dofs[d]) - lower[d]) / width[d];
    if (!(t >= 0.0 && t < cells[d])) return false;
    index += stride * static_cast<int>(t);
    stride *= cells[d];
  }
  const auto bit = static_cast<std::size_t>(index);
  return ((apart[bit / 32] >> (bit % 32)) & 1u) != 0;
}

double PairMap::apartShare() const {
  std::size_t set = 0;
  for (const std::uint32_t word : apart) set += static_cast<std::size_t>(__builtin_popcount(word));
  return static_cast<double>(set) / static_cast<double>(cells[0] * cells[1] * cells[2]);
}

std::vector<PairMap> buildPairMaps(const RobotModel& model, const SphereModel& spheres,
                                   const PairMapOptions& options) {
  std::vector<PairMap> maps;
  const int links = static_cast<int>(model.links().size());
  for (int a = 0; a < links; ++a) {
    for (int b = a + 1; b < links; ++b) {
      const LinkSpheres& sa = spheres.links[static_cast<std::size_t>(a)];
      const LinkSpheres& sb = spheres.links[static_cast<std::size_t>(b)];
      if (sa.root < 0 || sb.root < 0 || model.isCollisionDisabled(a, b)) continue;
      const int ancestor = commonAncestor(model, a, b);
      const std::vector<int> pathA = jointsUpTo(model, a, ancestor);
      const std::vector<int> pathB = jointsUpTo(model, b, ancestor);
      PairMap map;
      map.link_a = a;
      map.link_b = b;
      int count = 0;
      bool usable = true;
      for (const std::vector<int>* path : {&pathA, &pathB})
        for (const int j : *path) {
          const Joint& joint = model.joints()[static_cast<std::size_t>(j)];
          if (joint.type == Joint::Type::kPrismatic) usable = false;
          if (joint.type != Joint::Type::kRevolute) continue;
          if (std::find(map.dofs, map.dofs + count, joint.dof) != map.dofs + count) continue;
          if (count == PairMap::kMaxDofs) {
            usable = false;
            break;
          }
          map.dofs[count++] = joint.dof;
        }
      if (!usable || count == 0) continue;
      std::sort(map.dofs, map.dofs + count);
      const int cells[] = {options.cells_one, options.cells_two, options.cells_three};
      for (int d = 0; d < count; ++d) {
        map.cells[d] = cells[count - 1];
        map.lower[d] = model.lowerLimits()(map.dofs[d]);
        map.width[d] = (model.upperLimits()(map.dofs[d]) - map.lower[d]) / map.cells[d];
        if (!std::isfinite(map.width[d]) || !(map.width[d] > 0.0)) usable = false;
      }
      if (!usable) continue;
      map.apart.assign(
          static_cast<std::size_t>(map.cells[0] * map.cells[1] * map.cells[2] + 31) / 32, 0u);
      Side sideA(model, sa, pathA), sideB(model, sb, pathB);
      MapBuilder(map, sideA, sideB, options.clearance)
          .fill({0, 0, 0}, {map.cells[0], map.cells[1], map.cells[2]});
      if (map.apartShare() > 0.0) maps.push_back(std::move(map));
    }
  }
  return maps;
}

}  // namespace hfts::robot
