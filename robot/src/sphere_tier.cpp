#include "sphere_tier.h"

#include <algorithm>
#include <cmath>

namespace hfts::robot {
namespace {

bool touches(const SphereTier::Item& item, const Eigen::Vector3d& center, double radius) {
  return primitiveSignedDistance(item.type, item.size, item.to_local * center) <= radius;
}

/// A sphere (world frame) holding the whole item.
LinkSphere boundingSphere(const SphereTier::Item& item) {
  double radius = 0.0;
  switch (item.type) {
    case CollisionShape::Type::kBox:
      radius = 0.5 * item.size.norm();
      break;
    case CollisionShape::Type::kCylinder:
      radius = std::hypot(item.size.x(), 0.5 * item.size.y());
      break;
    case CollisionShape::Type::kSphere:
      radius = item.size.x();
      break;
  }
  return {item.to_local.inverse().translation(), radius};
}

}  // namespace

SphereTier::SphereTier(const RobotModel& model, const Eigen::Isometry3d& base,
                       std::vector<Item> items)
    : base_(base), items_(std::move(items)), spheres_(model.spheres()) {
  const std::size_t links = model.links().size();
  static_.assign(links, true);
  for (std::size_t l = 1; l < links; ++l) {
    const Joint& joint = model.joints()[static_cast<std::size_t>(model.links()[l].parent_joint)];
    static_[l] = joint.dof < 0 && static_[static_cast<std::size_t>(joint.parent_link)];
  }
  fingertip_.assign(links, false);
  for (const Fingertip& f : model.fingertips()) fingertip_[static_cast<std::size_t>(f.link)] = true;
  skip_item_.assign(links, std::vector<bool>(items_.size(), false));
  for (const Item& item : items_) bounds_.push_back(boundingSphere(item));
  root_.assign(links, 0);
  for (std::size_t l = 0; l < links; ++l)
    if (spheres_.links[l].root >= 0) root_[l] = static_cast<std::size_t>(spheres_.links[l].root);
  for (std::size_t a = 0; a < links; ++a)
    for (std::size_t b = a + 1; b < links; ++b)
      if (spheres_.links[a].root >= 0 && spheres_.links[b].root >= 0 &&
          !model.isCollisionDisabled(static_cast<int>(a), static_cast<int>(b))) {
        const double reach = spheres_.links[a].tree[root_[a]].sphere.radius +
                             spheres_.links[b].tree[root_[b]].sphere.radius;
        self_pairs_.push_back({a, b, reach * reach});
      }
  world_.resize(links);
  first_node_.resize(links);
  std::size_t nodes = 0;
  for (std::size_t l = 0; l < links; ++l) {
    first_node_[l] = nodes;
    nodes += spheres_.links[l].tree.size();
  }
  centers_.resize(nodes);
  stamp_.assign(nodes, 0);
}

void SphereTier::startQuery(const LinkPoses& poses) {
  if (++query_ == 0) {  // wrapped around: no stamp may look current
    std::fill(stamp_.begin(), stamp_.end(), 0);
    query_ = 1;
  }
  for (std::size_t l = 0; l < spheres_.links.size(); ++l) {
    if (spheres_.links[l].root < 0) continue;
    world_[l] = base_ * poses[l];
    center(l, spheres_.links[l].root);
  }
}

const Eigen::Vector3d& SphereTier::center(std::size_t link, int node) const {
  const std::size_t i = first_node_[link] + static_cast<std::size_t>(node);
  if (stamp_[i] != query_) {
    centers_[i] =
        world_[link] * spheres_.links[link].tree[static_cast<std::size_t>(node)].sphere.center;
    stamp_[i] = query_;
  }
  return centers_[i];
}

void SphereTier::skipStatic(int link, std::size_t item) {
  skip_item_[static_cast<std::size_t>(link)][item] = true;
}

void SphereTier::skipStaticPair(int a, int b) {
  // (Not std::minmax of the casts: its pair would refer to the dead temporaries.)
  const std::size_t low = static_cast<std::size_t>(std::min(a, b));
  const std::size_t high = static_cast<std::size_t>(std::max(a, b));
  self_pairs_.erase(std::remove_if(self_pairs_.begin(), self_pairs_.end(),
                                   [&](const SelfPair& p) { return p.a == low && p.b == high; }),
                    self_pairs_.end());
}

bool SphereTier::nodeTouchesItem(std::size_t link, int node, const Item& item) const {
  const SphereNode& n = spheres_.links[link].tree[static_cast<std::size_t>(node)];
  if (!touches(item, center(link, node), n.sphere.radius)) return false;
  return n.leaf() || nodeTouchesItem(link, n.left, item) || nodeTouchesItem(link, n.right, item);
}

bool SphereTier::itemTouches(std::size_t link, std::size_t item, bool allowFingertipContact) const {
  if (skip_item_[link][item] || (allowFingertipContact && items_[item].target && fingertip_[link]))
    return false;
  // The item's bounding sphere first: one distance, no frame change.
  const int root = static_cast<int>(root_[link]);
  const double reach = spheres_.links[link].tree[root_[link]].sphere.radius + bounds_[item].radius;
  if ((center(link, root) - bounds_[item].center).squaredNorm() > reach * reach) return false;
  return nodeTouchesItem(link, root, items_[item]);
}

bool SphereTier::linksTouch(std::size_t a, std::size_t b) const {
  return nodesTouch(a, spheres_.links[a].root, b, spheres_.links[b].root);
}

bool SphereTier::nodesTouch(std::size_t a, int nodeA, std::size_t b, int nodeB) const {
  const SphereNode& na = spheres_.links[a].tree[static_cast<std::size_t>(nodeA)];
  const SphereNode& nb = spheres_.links[b].tree[static_cast<std::size_t>(nodeB)];
  const double reach = na.sphere.radius + nb.sphere.radius;
  if ((center(a, nodeA) - center(b, nodeB)).squaredNorm() > reach * reach) return false;
  if (na.leaf() && nb.leaf()) return true;
  // Descend the larger node (or the one that can).
  if (nb.leaf() || (!na.leaf() && na.sphere.radius >= nb.sphere.radius))
    return nodesTouch(a, na.left, b, nodeB) || nodesTouch(a, na.right, b, nodeB);
  return nodesTouch(a, nodeA, b, nb.left) || nodesTouch(a, nodeA, b, nb.right);
}

}  // namespace hfts::robot
