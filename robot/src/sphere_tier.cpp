#include "sphere_tier.h"

#include <cmath>
#include <limits>

namespace hfts::robot {
namespace {

/// The float nearest to x that is not below it.
float roundedUp(double x) {
  const auto f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

void copyRotation(const Eigen::Matrix3d& r, float* out) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[3 * i + j] = static_cast<float>(r(i, j));
}

void copyVector(const Eigen::Vector3d& v, float* out) {
  for (int i = 0; i < 3; ++i) out[i] = static_cast<float>(v(i));
}

/// Radius of a sphere around the item's centre holding the whole item.
double boundingRadius(const SphereTier::Item& item) {
  switch (item.type) {
    case CollisionShape::Type::kBox:
      return 0.5 * item.size.norm();
    case CollisionShape::Type::kCylinder:
      return std::hypot(item.size.x(), 0.5 * item.size.y());
    case CollisionShape::Type::kSphere:
      return item.size.x();
  }
  return 0.0;
}

}  // namespace

SphereTier::SphereTier(const CollisionModel& collision, const Eigen::Isometry3d& base,
                       std::vector<Item> items, double margin)
    : model_(collision), margin_(margin), batch_(kernel::batchSize()) {
  const RobotModel& model = collision.robot;
  compileRobot(model, base);
  kernel::buildWideTrees(program_);
  compileItems(items);
  const std::size_t links = model.links().size();
  skip_item_.assign(links, std::vector<bool>(items.size(), false));
  may_collide_.assign(links, std::vector<bool>(links, false));
  for (std::size_t a = 0; a < links; ++a)
    for (std::size_t b = a + 1; b < links; ++b)
      may_collide_[a][b] = program_.root[a] >= 0 && program_.root[b] >= 0 &&
                           !model.isCollisionDisabled(static_cast<int>(a), static_cast<int>(b));
  listPairs();
}

void SphereTier::compileRobot(const RobotModel& model, const Eigen::Isometry3d& base) {
  kernel::Program& p = program_;
  p.num_dofs = model.numDofs();
  p.num_links = static_cast<int>(model.links().size());
  copyRotation(base.linear(), p.base);
  copyVector(base.translation(), p.base + 9);
  static_.assign(model.links().size(), true);
  for (const Joint& joint : model.joints()) {
    kernel::FkStep step;
    step.parent = joint.parent_link;
    step.child = joint.child_link;
    step.dof = joint.type == Joint::Type::kFixed ? -1 : joint.dof;
    step.multiplier = static_cast<float>(joint.multiplier);
    step.offset = static_cast<float>(joint.offset);
    copyVector(joint.origin.translation(), step.t);
    copyRotation(joint.rotation_fixed, step.a);
    copyRotation(joint.rotation_cos, step.b);
    copyRotation(joint.rotation_sin, step.c);
    copyVector(joint.slide, step.dt);
    step.revolute = joint.type == Joint::Type::kRevolute;
    p.steps.push_back(step);
    const auto child = static_cast<std::size_t>(joint.child_link);
    static_[child] = step.dof < 0 && static_[static_cast<std::size_t>(joint.parent_link)];
  }
  p.root.assign(model.links().size(), -1);
  for (std::size_t l = 0; l < model_.spheres.links.size(); ++l) {
    const LinkSpheres& link = model_.spheres.links[l];
    if (link.root < 0) continue;
    const int first = static_cast<int>(p.nodes.size());
    for (const SphereNode& node : link.tree) {
      kernel::Node n;
      n.x = static_cast<float>(node.sphere.center.x());
      n.y = static_cast<float>(node.sphere.center.y());
      n.z = static_cast<float>(node.sphere.center.z());
      n.r = roundedUp(node.sphere.radius + margin_) + kernel::kPadding;
      n.left = node.left < 0 ? -1 : first + node.left;
      n.right = node.right < 0 ? -1 : first + node.right;
      p.nodes.push_back(n);
    }
    p.root[l] = first + link.root;
  }
}

void SphereTier::compileItems(const std::vector<Item>& items) {
  for (const Item& item : items) {
    kernel::Item k;
    k.target = item.target;
    copyRotation(item.to_local.linear(), k.rotation);
    copyVector(item.to_local.translation(), k.translation);
    const Eigen::Vector3d center = item.to_local.inverse().translation();
    copyVector(center, k.bound);
    k.bound[3] = roundedUp(boundingRadius(item));
    switch (item.type) {
      case CollisionShape::Type::kBox:
        k.type = kernel::ItemType::kBox;
        copyVector(item.size / 2, k.half);
        break;
      case CollisionShape::Type::kCylinder:
        k.type = kernel::ItemType::kCylinder;
        k.half[0] = static_cast<float>(item.size.x());
        k.half[1] = static_cast<float>(item.size.y() / 2);
        break;
      case CollisionShape::Type::kSphere:
        k.type = kernel::ItemType::kSphere;
        k.half[0] = static_cast<float>(item.size.x());
        break;
    }
    if (item.grid && item.type == CollisionShape::Type::kBox) {
      k.type = kernel::ItemType::kGrid;
      k.values = item.grid->values;
      copyVector(item.grid->origin, k.origin);
      k.spacing = static_cast<float>(item.grid->spacing);
      for (int i = 0; i < 3; ++i) k.dims[i] = item.grid->dims[static_cast<std::size_t>(i)];
    }
    program_.items.push_back(k);
  }
}

void SphereTier::listPairs() {
  program_.env.clear();
  program_.self.clear();
  const std::size_t links = program_.root.size();
  for (std::size_t l = 0; l < links; ++l) {
    if (program_.root[l] < 0) continue;
    for (std::size_t i = 0; i < program_.items.size(); ++i)
      if (!skip_item_[l][i])
        program_.env.push_back({static_cast<std::uint16_t>(l), static_cast<std::uint16_t>(i)});
  }
  for (std::size_t a = 0; a < links; ++a)
    for (std::size_t b = a + 1; b < links; ++b)
      if (may_collide_[a][b])
        program_.self.push_back({static_cast<std::uint16_t>(a), static_cast<std::uint16_t>(b)});
  kernel::buildLookups(program_);  // self_index, read below
  program_.self_maps.assign(program_.self.size(), {});
  if (margin_ > 0.0) return;  // the maps prove pairs apart, not a margin apart
  for (const PairMap& map : model_.pair_maps) {
    const int pair = program_.self_index[static_cast<std::size_t>(map.link_a) * links +
                                         static_cast<std::size_t>(map.link_b)];
    if (pair < 0) continue;  // not tested (disabled, or static and clear)
    kernel::SelfMap& out = program_.self_maps[static_cast<std::size_t>(pair)];
    static_assert(kernel::SelfMap::kDofs == PairMap::kMaxDofs);
    int stride = 1;
    for (int k = 0; k < PairMap::kMaxDofs; ++k) {
      const bool used = map.dofs[k] >= 0;
      out.dof[k] = used ? map.dofs[k] : map.dofs[0];
      out.lower[k] = used ? static_cast<float>(map.lower[k]) : 0.0f;
      out.inverse[k] = used ? static_cast<float>(1.0 / map.width[k]) : 0.0f;
      out.cells[k] = static_cast<float>(map.cells[k]);
      out.stride[k] = stride;
      stride *= map.cells[k];
    }
    out.bits = map.apart.data();
  }
}

void SphereTier::skipStatic(int link, std::size_t item) {
  skip_item_[static_cast<std::size_t>(link)][item] = true;
}

void SphereTier::skipStaticPair(int a, int b) {
  may_collide_[static_cast<std::size_t>(std::min(a, b))][static_cast<std::size_t>(std::max(a, b))] =
      false;
}

void SphereTier::load(const Eigen::VectorXd* const* q, std::size_t count,
                      std::vector<float>& scratch) const {
  prepareBatch(scratch);
  if (count == 1) {
    for (int d = 0; d < program_.num_dofs; ++d)
      scratch[static_cast<std::size_t>(d)] = static_cast<float>((*q[0])(d));
    return;
  }
  for (std::size_t lane = 0; lane < count; ++lane)
    for (int d = 0; d < program_.num_dofs; ++d)
      scratch[static_cast<std::size_t>(d) * batch_ + lane] = static_cast<float>((*q[lane])(d));
}

SphereTier::Pair SphereTier::pair(std::uint32_t index) const {
  if (index < program_.env.size()) {
    const kernel::EnvPair& p = program_.env[index];
    return {p.link, -1, p.item};
  }
  const kernel::SelfPair& p = program_.self[index - program_.env.size()];
  return {p.a, p.b, 0};
}

}  // namespace hfts::robot
