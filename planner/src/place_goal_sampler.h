#pragma once
// The goal samplers of a placement (docs/placement.md "Placing"), internal
// to the planner library. A goal is an arm configuration of the robot
// holding the object with the palm `height` above where it puts the object
// down (the pre-place), from which the descent, the release and the retreat
// are free and where the object, released, stays. The coupled sampler
// searches the placements as a hierarchy (resting face, then ever finer
// cells of the region and yaws) with the paper's goal sampler (Algorithm 2,
// the goal hierarchy cache's C_free-proximity ratings), a placement
// objective in place of Eq. (1); the decoupled one draws a stable
// placement first and plans to it.

#include <Eigen/Geometry>

#include <cstdint>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "grasp/stable_placements.h"
#include "planner/goal_hierarchy_cache.h"
#include "planner/goal_sampler.h"
#include "planner/place_goal.h"
#include "planner/plan_result.h"
#include "robot/arm_ik.h"
#include "robot/collision_checker.h"

namespace hfts::planner {

/// Checks the rest of a placement from its pre-place configuration (the
/// descent, the release, the retreat, the rest): the rest of the plan, or
/// none with the reason counted in `rejected`.
using PlaceFinisher = std::function<std::optional<Placement>(
    const Eigen::Isometry3d& objectPose, const grasp::RestingFace& face,
    const Eigen::VectorXd& prePlace, PlaceRejections& rejected)>;

/// What both samplers work with (everything outliving the sampler).
struct PlaceSamplingContext {
  const PlaceRegion* region = nullptr;
  const std::vector<grasp::RestingFace>* faces = nullptr;    ///< placeFaces(), not empty
  Eigen::Vector3d center_of_mass = Eigen::Vector3d::Zero();  ///< object frame
  Eigen::Isometry3d object_in_palm = Eigen::Isometry3d::Identity();
  double height = 0.1;  ///< of the pre-place above the place (m)
  const robot::ArmIk* ik = nullptr;
  /// The robot holding the object (hand fixed) among the obstacles.
  robot::CollisionChecker* checker = nullptr;
  std::mt19937_64* rng = nullptr;
  Eigen::Isometry3d robot_base = Eigen::Isometry3d::Identity();
  /// Where the carry starts (the lift's end): the hand's posture and the
  /// IK branch nearest to it.
  Eigen::VectorXd start;
  PlaceFinisher finish;
};

/// The hierarchy of placements: level 1 a resting face, a 2 x 2 split of
/// the region and four yaw sectors; every level below halves the cell in
/// x and y and the yaw sector (eight children). Encoded in an HftsNode's
/// parts: face, x cell, y cell, yaw sector.
class PlaceHierarchy final : public GoalHierarchy {
 public:
  /// Cells of the region's rectangle (in its frame, the area's bounding
  /// box within the top when it has one) down to at most `leafCell` (m).
  PlaceHierarchy(const PlaceRegion& region, int faces, double leafCell = 0.02);

  grasp::HftsNode root() const override { return {}; }
  bool isLeaf(const grasp::HftsNode& node) const override { return node.level == levels_; }
  std::uint64_t numChildren(const grasp::HftsNode& node) const override;
  double numLeaves(const grasp::HftsNode& node) const override;
  /// Child number `index` (0 <= index < numChildren).
  grasp::HftsNode child(const grasp::HftsNode& parent, std::uint64_t index) const;

  /// The node's representative: the centre of its cell (world x, y) and
  /// of its yaw sector (rad).
  Eigen::Vector2d cellCentre(const grasp::HftsNode& node) const;
  double yaw(const grasp::HftsNode& node) const;

 private:
  const PlaceRegion& region_;
  int faces_;
  int levels_;
  Eigen::Vector2d low_, high_;  // the searched rectangle in the region's frame
};

class PlacementSampler : public GoalSampler {
 public:
  /// The placement whose pre-place `q` is (a goal handed out), or null.
  const Placement* placementOf(const Eigen::VectorXd& q) const;
  const PlaceRejections& rejections() const { return rejected_; }

 protected:
  /// Throws std::invalid_argument for a context with a null member or no faces.
  explicit PlacementSampler(PlaceSamplingContext context);

  /// The object resting on face `face` at (x, y), turned by `yaw`.
  Eigen::Isometry3d placement(int face, const Eigen::Vector2d& xy, double yaw) const;
  /// Whether the hand alone, as it holds the object, is free of everything
  /// with the object at `pose` (robot::CollisionChecker::handInCollision):
  /// no finger between the object and its support, no palm in it.
  bool handFits(const Eigen::Isometry3d& pose) const;
  /// The free pre-place configurations of the object at `pose`: the arm's
  /// IK solutions for the palm `height` above where it holds it there.
  std::vector<Eigen::VectorXd> prePlaces(const Eigen::Isometry3d& pose, bool count);
  /// The pre-place configurations of a placement, those of a leaf (`leaf`)
  /// whose placement is supported and finishes marked as goals.
  std::vector<CachedConfiguration> configurationsOf(int face, const Eigen::Isometry3d& pose,
                                                    bool leaf);
  /// A goal configuration as the planner takes it.
  GoalSample handOut(const CachedConfiguration& goal);

  PlaceSamplingContext context_;
  PlaceRejections rejected_;

 private:
  std::vector<Placement> goals_;  // every finished placement
};

/// Algorithm 2 over the placement hierarchy with the goal hierarchy cache.
class HierarchicalPlaceSampler final : public PlacementSampler {
 public:
  HierarchicalPlaceSampler(PlaceSamplingContext context, HftsGoalSamplerOptions options);

  GoalSample sample(const FreeSpaceDistances& knowledge,
                    const std::function<bool()>& stop) override;

 private:
  /// SAMPLENEWCHILD: the best by the placement objective of a few
  /// uncached children drawn at random.
  int sampleNewChild(int parent);
  /// The placement objective of a node: its face's tipping angle (of the
  /// stablest face's) times the room its contact polygon leaves to the
  /// region's edges (up to 5 cm); 0 when its placement is not supported
  /// or the hand holding the object there meets something (handFits).
  double objective(const grasp::HftsNode& node) const;
  Eigen::Isometry3d placementOf(const grasp::HftsNode& node) const;

  HftsGoalSamplerOptions options_;
  PlaceHierarchy hierarchy_;
  GoalHierarchyCache cache_;
  std::vector<Eigen::VectorXd> approximate_;
  double stablest_ = 0.0;
};

/// The decoupled baseline: each call draws a stable placement on the
/// region (samplePlacement) and returns its pre-place when it finishes.
class DecoupledPlaceSampler final : public PlacementSampler {
 public:
  explicit DecoupledPlaceSampler(PlaceSamplingContext context);

  GoalSample sample(const FreeSpaceDistances& knowledge,
                    const std::function<bool()>& stop) override;
};

}  // namespace hfts::planner
