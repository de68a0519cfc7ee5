#pragma once
// The first tier of collision checking: the robot's sphere model
// (link_spheres.h) against the scene's primitives and bounding boxes and
// against itself. It names the pairs (link and item, or two links) whose
// spheres touch; only those go on to FCL, and a configuration without such
// a pair is certainly free, so the checker's answer is exactly FCL's
// (docs/collision.md). Internal to the robot library.

#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

#include "robot/kinematics.h"
#include "robot/link_spheres.h"
#include "robot/robot_model.h"

namespace hfts::robot {

class SphereTier {
 public:
  /// Something of the environment as tier 1 sees it: a primitive, or the
  /// bounding box of a mesh (which holds the mesh, so it is conservative).
  struct Item {
    CollisionShape::Type type = CollisionShape::Type::kBox;
    Eigen::Vector3d size = Eigen::Vector3d::Zero();
    Eigen::Isometry3d to_local = Eigen::Isometry3d::Identity();  ///< world -> item frame
    bool target = false;
  };

  /// Uses the model's sphere model (RobotModel::spheres()).
  SphereTier(const RobotModel& model, const Eigen::Isometry3d& base, std::vector<Item> items);

  /// Drops the pair (link, item) from the check: for a link that does not
  /// move with any DoF and that FCL found clear of the item once.
  void skipStatic(int link, std::size_t item);
  /// Drops a pair of links that never move relative to each other and that
  /// FCL found clear once.
  void skipStaticPair(int a, int b);

  /// A pair whose spheres touch: `link` and environment item `item`, or
  /// `link` and `other_link` when that is >= 0.
  struct Pair {
    int link = -1;
    int other_link = -1;
    std::size_t item = 0;
  };

  /// Calls visit(pair) for each pair of the robot at `poses` (base frame)
  /// whose spheres touch: a link and an item, or two links that may
  /// collide; stops and returns true as soon as visit returns true. No call:
  /// certainly free. With `allowFingertipContact`, fingertip links are not
  /// paired with the target (the grasp-aware rule, as in the exact check).
  template <typename Visit>
  bool forEachTouchingPair(const LinkPoses& poses, bool allowFingertipContact, Visit&& visit) {
    startQuery(poses);
    for (std::size_t l = 0; l < spheres_.links.size(); ++l) {
      if (spheres_.links[l].root < 0) continue;
      for (std::size_t i = 0; i < items_.size(); ++i)
        if (itemTouches(l, i, allowFingertipContact) && visit(Pair{static_cast<int>(l), -1, i}))
          return true;
    }
    for (const SelfPair& p : self_pairs_) {
      // Most pairs end at their root spheres: tested here, without a call.
      const Eigen::Vector3d& a = centers_[first_node_[p.a] + root_[p.a]];
      const Eigen::Vector3d& b = centers_[first_node_[p.b] + root_[p.b]];
      if ((a - b).squaredNorm() > p.reach_squared) continue;
      if (linksTouch(p.a, p.b) && visit(Pair{static_cast<int>(p.a), static_cast<int>(p.b), 0}))
        return true;
    }
    return false;
  }

  /// Links whose pose does not depend on any DoF (the base and what is
  /// fixed to it).
  bool isStatic(int link) const { return static_[static_cast<std::size_t>(link)]; }
  const SphereModel& spheres() const { return spheres_; }

 private:
  /// Forgets the world centres of the previous query, places the links at
  /// `poses` and transforms every link's root sphere.
  void startQuery(const LinkPoses& poses);
  /// A node's centre in the world frame this query (transformed once, on
  /// first use: most nodes are never reached).
  const Eigen::Vector3d& center(std::size_t link, int node) const;
  bool itemTouches(std::size_t link, std::size_t item, bool allowFingertipContact) const;
  bool linksTouch(std::size_t a, std::size_t b) const;
  /// Descends the link's sphere tree from `node`: does a leaf touch the item?
  bool nodeTouchesItem(std::size_t link, int node, const Item& item) const;
  /// Descends two links' sphere trees: do two leaves touch?
  bool nodesTouch(std::size_t a, int nodeA, std::size_t b, int nodeB) const;

  Eigen::Isometry3d base_;
  std::vector<Item> items_;
  std::vector<LinkSphere> bounds_;  ///< [item]: a sphere holding it (world frame)
  const SphereModel& spheres_;
  std::vector<bool> static_, fingertip_;
  std::vector<std::vector<bool>> skip_item_;  ///< [link][item]
  struct SelfPair {
    std::size_t a, b;
    double reach_squared;  ///< (root radius of a + root radius of b)^2
  };
  std::vector<SelfPair> self_pairs_;
  std::vector<std::size_t> root_;        ///< [link]: its root node (0 for a link without one)
  LinkPoses world_;                      ///< scratch: each link's world pose in the current query
  std::vector<std::size_t> first_node_;  ///< [link]: its nodes' offset in centers_
  mutable std::vector<Eigen::Vector3d> centers_;  ///< scratch: node centres this query
  mutable std::vector<std::uint32_t> stamp_;      ///< query_ when centers_[i] was set
  std::uint32_t query_ = 0;
};

}  // namespace hfts::robot
