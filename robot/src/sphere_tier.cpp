#include "sphere_tier.h"

#include <algorithm>

namespace hfts::robot {
namespace {

/// One sphere around all of a link's spheres (centred on their centroid).
LinkSphere boundOf(const std::vector<LinkSphere>& spheres) {
  LinkSphere bound;
  if (spheres.empty()) return bound;
  for (const LinkSphere& s : spheres) bound.center += s.center;
  bound.center /= static_cast<double>(spheres.size());
  for (const LinkSphere& s : spheres)
    bound.radius = std::max(bound.radius, (s.center - bound.center).norm() + s.radius);
  return bound;
}

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
  for (const LinkSpheres& link : spheres_.links) bounds_.push_back(boundOf(link.spheres));
  skip_item_.assign(links, std::vector<bool>(items_.size(), false));
  for (std::size_t a = 0; a < links; ++a)
    for (std::size_t b = a + 1; b < links; ++b)
      if (!spheres_.links[a].spheres.empty() && !spheres_.links[b].spheres.empty() &&
          !model.isCollisionDisabled(static_cast<int>(a), static_cast<int>(b)))
        self_pairs_.emplace_back(static_cast<int>(a), static_cast<int>(b));
  centers_.resize(links);
  bound_centers_.resize(links);
  world_.resize(links);
  placed_.assign(links, false);
}

void SphereTier::skipStatic(int link, std::size_t item) {
  skip_item_[static_cast<std::size_t>(link)][item] = true;
}

void SphereTier::skipStaticPair(int a, int b) {
  const std::pair<int, int> pair(std::min(a, b), std::max(a, b));
  self_pairs_.erase(std::remove(self_pairs_.begin(), self_pairs_.end(), pair), self_pairs_.end());
}

const std::vector<Eigen::Vector3d>& SphereTier::placedCenters(std::size_t link) {
  if (!placed_[link]) {
    std::vector<Eigen::Vector3d>& centers = centers_[link];
    centers.clear();
    for (const LinkSphere& s : spheres_.links[link].spheres)
      centers.push_back(world_[link] * s.center);
    placed_[link] = true;
  }
  return centers_[link];
}

void SphereTier::addTouchingItems(std::size_t link, bool allowFingertipContact,
                                  std::vector<Pair>& pairs) {
  const std::vector<LinkSphere>& spheres = spheres_.links[link].spheres;
  for (std::size_t i = 0; i < items_.size(); ++i) {
    const Item& item = items_[i];
    if (skip_item_[link][i] || (allowFingertipContact && item.target && fingertip_[link])) continue;
    if (!touches(item, bound_centers_[link], bounds_[link].radius)) continue;
    const std::vector<Eigen::Vector3d>& centers = placedCenters(link);
    for (std::size_t s = 0; s < spheres.size(); ++s)
      if (touches(item, centers[s], spheres[s].radius)) {
        pairs.push_back({static_cast<int>(link), -1, i});
        break;
      }
  }
}

bool SphereTier::linksTouch(std::size_t a, std::size_t b) {
  if ((bound_centers_[a] - bound_centers_[b]).norm() > bounds_[a].radius + bounds_[b].radius)
    return false;
  const std::vector<LinkSphere>& sa = spheres_.links[a].spheres;
  const std::vector<LinkSphere>& sb = spheres_.links[b].spheres;
  const std::vector<Eigen::Vector3d>& ca = placedCenters(a);
  const std::vector<Eigen::Vector3d>& cb = placedCenters(b);
  for (std::size_t i = 0; i < sa.size(); ++i)
    for (std::size_t j = 0; j < sb.size(); ++j)
      if ((ca[i] - cb[j]).squaredNorm() <=
          (sa[i].radius + sb[j].radius) * (sa[i].radius + sb[j].radius))
        return true;
  return false;
}

void SphereTier::touchingPairs(const LinkPoses& poses, bool allowFingertipContact,
                               std::vector<Pair>& pairs) {
  pairs.clear();
  std::fill(placed_.begin(), placed_.end(), false);
  for (std::size_t l = 0; l < spheres_.links.size(); ++l) {
    if (spheres_.links[l].spheres.empty()) continue;
    world_[l] = base_ * poses[l];
    bound_centers_[l] = world_[l] * bounds_[l].center;
    addTouchingItems(l, allowFingertipContact, pairs);
  }
  for (const auto& [a, b] : self_pairs_)
    if (linksTouch(static_cast<std::size_t>(a), static_cast<std::size_t>(b)))
      pairs.push_back({a, b, 0});
}

}  // namespace hfts::robot
