#pragma once
// The first tier of collision checking: the robot's sphere model
// (link_spheres.h) against the scene's primitives, the meshes' distance
// grids and itself. It names the pairs (link and item, or two links) whose
// spheres touch; only those go on to FCL, and a configuration without such
// a pair is certainly free, so the checker's answer is exactly FCL's
// (docs/collision.md). A batch of configurations is tested at once, one per
// SIMD lane (sphere_kernel.h). Internal to the robot library.

#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "robot/collision_model.h"
#include "sphere_kernel.h"

namespace hfts::robot {

class SphereTier {
 public:
  /// Lower bounds of the signed distance to a mesh at grid nodes (the
  /// mesh's frame), e.g. a db::DistanceGrid's; the values must outlive the tier.
  struct Grid {
    const float* values = nullptr;  ///< x fastest
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    double spacing = 0.0;
    std::array<int, 3> dims{0, 0, 0};
  };

  /// Something of the environment as tier 1 sees it: a primitive, or a
  /// mesh as its bounding box (which holds it), refined by its distance
  /// grid when it has one.
  struct Item {
    CollisionShape::Type type = CollisionShape::Type::kBox;
    Eigen::Vector3d size = Eigen::Vector3d::Zero();
    Eigen::Isometry3d to_local = Eigen::Isometry3d::Identity();  ///< world -> item frame
    bool target = false;
    /// For a mesh (a kBox around it): its grid, origin given in the box's frame.
    std::optional<Grid> grid;
  };

  /// The model's spheres and pair maps against `items`; the model must
  /// outlive the tier. Read-only once the skips below are listed: threads
  /// may test configurations at once, each with its own scratch.
  /// With a `margin` (m, > 0) every robot sphere grows by it: a pair the
  /// tier calls clear is then more than the margin apart (a clearance
  /// check, CollisionScene's), and the pair maps, which prove pairs apart
  /// but not by a margin, are not used.
  SphereTier(const CollisionModel& model, const Eigen::Isometry3d& base, std::vector<Item> items,
             double margin = 0.0);

  /// Drops the pair (link, item) from the check: for a link that does not
  /// move with any DoF and that FCL found clear of the item once. Takes
  /// effect at listPairs().
  void skipStatic(int link, std::size_t item);
  /// Drops a pair of links that never move relative to each other and that
  /// FCL found clear once. Takes effect at listPairs().
  void skipStaticPair(int a, int b);
  /// Program::env and Program::self from the pairs not skipped.
  void listPairs();

  /// A pair whose spheres touch: `link` and environment item `item`, or
  /// `link` and `other_link` when that is >= 0.
  struct Pair {
    int link = -1;
    int other_link = -1;
    std::size_t item = 0;
  };

  /// Configurations tested at once (the SIMD width: 4, 8 or 16).
  std::size_t batchSize() const { return batch_; }

  /// Tests configurations q[0] .. q[count - 1] (count <= batchSize()) and
  /// calls visit(pair, lanes) for each pair whose spheres touch, with bit i
  /// of `lanes` set where they touch in q[i], in the order of the exact
  /// check (link-item pairs by link, then item; then link pairs); `visit`
  /// returns the configurations still to be tested (as bits) and the tier
  /// stops when none is left. A configuration without a call is certainly
  /// free. Fingertips are paired with the target under either rule: the
  /// exact check decides how deep they may be. `scratch` is the calling
  /// thread's own.
  template <typename Visit>
  void forEachTouchingPair(const Eigen::VectorXd* const* q, std::size_t count,
                           std::vector<float>& scratch, Visit&& visit) const {
    load(q, count, scratch);
    forEachTouchingPairLoaded(count, scratch, visit);
  }

  /// The batch layout of `scratch` (single precision, DoF-major: DoF d of
  /// configuration i at d * batchSize() + i), sized for a batch, for a
  /// caller that writes its configurations there itself.
  void prepareBatch(std::vector<float>& scratch) const {
    scratch.resize(static_cast<std::size_t>(program_.num_dofs) * batch_);
  }
  /// forEachTouchingPair on the `count` (<= batchSize()) configurations a
  /// caller wrote into `scratch` in the batch layout (prepareBatch); for
  /// one configuration it moves that configuration's values to the front
  /// of `scratch` (the single layout) in place.
  template <typename Visit>
  void forEachTouchingPairWritten(std::size_t count, std::vector<float>& scratch,
                                  Visit&& visit) const {
    if (count == 1)  // one configuration: its DoF in order
      for (std::size_t d = 1; d < static_cast<std::size_t>(program_.num_dofs); ++d)
        scratch[d] = scratch[d * batch_];
    forEachTouchingPairLoaded(count, scratch, visit);
  }

  /// The pair of a kernel pair index.
  Pair pair(std::uint32_t index) const;

  /// Links whose pose does not depend on any DoF (the base and what is
  /// fixed to it).
  bool isStatic(int link) const { return static_[static_cast<std::size_t>(link)]; }
  /// Whether environment item `item` is the target object.
  bool isTarget(std::size_t item) const { return program_.items[item].target; }

 private:
  void compileRobot(const RobotModel& model, const Eigen::Isometry3d& base);
  void compileItems(const std::vector<Item>& items);
  /// The kernel on `count` configurations loaded into `scratch`.
  template <typename Visit>
  void forEachTouchingPairLoaded(std::size_t count, std::vector<float>& scratch,
                                 Visit& visit) const {
    struct Context {
      const SphereTier* tier;
      Visit* visit;
    } context{this, &visit};
    const kernel::Visit forward = [](void* raw, std::uint32_t index,
                                     std::uint32_t lanes) -> std::uint32_t {
      auto* c = static_cast<Context*>(raw);
      return (*c->visit)(c->tier->pair(index), lanes);
    };
    // One configuration: lanes over pairs; several: a configuration per lane.
    if (count == 1)
      kernel::findTouchingOne(program_, scratch.data(), forward, &context);
    else
      kernel::findTouching(program_, scratch.data(), count, forward, &context);
  }
  /// Writes the batch into `scratch` (single precision, DoF-major; one
  /// configuration: its DoF in order).
  void load(const Eigen::VectorXd* const* q, std::size_t count, std::vector<float>& scratch) const;

  const CollisionModel& model_;
  double margin_;
  std::size_t batch_;
  kernel::Program program_;
  std::vector<bool> static_;
  std::vector<std::vector<bool>> skip_item_;    ///< [link][item]
  std::vector<std::vector<bool>> may_collide_;  ///< [link][link]: a self pair to test
};

}  // namespace hfts::robot
