#include "sphere_tier.h"

#include <algorithm>

namespace hfts::robot {
namespace {

bool touches(const SphereTier::Item& item, const Eigen::Vector3d& center, double radius) {
  return primitiveSignedDistance(item.type, item.size, item.to_local * center) <= radius;
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
  for (std::size_t a = 0; a < links; ++a)
    for (std::size_t b = a + 1; b < links; ++b)
      if (!spheres_.links[a].spheres.empty() && !spheres_.links[b].spheres.empty() &&
          !model.isCollisionDisabled(static_cast<int>(a), static_cast<int>(b)))
        self_pairs_.emplace_back(static_cast<int>(a), static_cast<int>(b));
  world_.resize(links);
}

void SphereTier::skipStatic(int link, std::size_t item) {
  skip_item_[static_cast<std::size_t>(link)][item] = true;
}

void SphereTier::skipStaticPair(int a, int b) {
  const std::pair<int, int> pair(std::min(a, b), std::max(a, b));
  self_pairs_.erase(std::remove(self_pairs_.begin(), self_pairs_.end(), pair), self_pairs_.end());
}

bool SphereTier::nodeTouchesItem(std::size_t link, int node, const Item& item) const {
  const SphereNode& n = spheres_.links[link].tree[static_cast<std::size_t>(node)];
  if (!touches(item, world_[link] * n.sphere.center, n.sphere.radius)) return false;
  return n.leaf() || nodeTouchesItem(link, n.left, item) || nodeTouchesItem(link, n.right, item);
}

bool SphereTier::itemTouches(std::size_t link, std::size_t item, bool allowFingertipContact) const {
  if (skip_item_[link][item] || (allowFingertipContact && items_[item].target && fingertip_[link]))
    return false;
  return nodeTouchesItem(link, spheres_.links[link].root, items_[item]);
}

bool SphereTier::linksTouch(std::size_t a, std::size_t b) const {
  return nodesTouch(a, spheres_.links[a].root, b, spheres_.links[b].root);
}

bool SphereTier::nodesTouch(std::size_t a, int nodeA, std::size_t b, int nodeB) const {
  const SphereNode& na = spheres_.links[a].tree[static_cast<std::size_t>(nodeA)];
  const SphereNode& nb = spheres_.links[b].tree[static_cast<std::size_t>(nodeB)];
  const double reach = na.sphere.radius + nb.sphere.radius;
  if ((world_[a] * na.sphere.center - world_[b] * nb.sphere.center).squaredNorm() > reach * reach)
    return false;
  if (na.leaf() && nb.leaf()) return true;
  // Descend the larger node (or the one that can).
  if (nb.leaf() || (!na.leaf() && na.sphere.radius >= nb.sphere.radius))
    return nodesTouch(a, na.left, b, nodeB) || nodesTouch(a, na.right, b, nodeB);
  return nodesTouch(a, nodeA, b, nb.left) || nodesTouch(a, nodeA, b, nb.right);
}

}  // namespace hfts::robot
