#pragma once
// The FCL side of the collision checker (collision_checker.cpp), private
// to the robot library: what a collision object stands for (Tag), FCL
// geometry of primitives and meshes, the broadphase callbacks of each
// query (full rule, grasp rule, distance, the target against the
// obstacles, one object against the environment), and the environment as
// the sphere tier sees it. FCL's template-heavy headers stay in the
// robot library's .cpp files that include this.

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/bvh/BVH_model.h>

#include <Eigen/Geometry>

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "hfts_db/object_database.h"
#include "robot/collision_pair.h"
#include "robot/object_surface.h"
#include "robot/robot_model.h"
#include "robot/scene.h"
#include "sphere_tier.h"

namespace hfts::robot::fcl_query {

using Object = fcl::CollisionObjectd;
using Geometry = std::shared_ptr<fcl::CollisionGeometryd>;

/// What a collision object stands for.
struct Tag {
  int link = -1;        ///< robot link, or -1 for the environment
  bool target = false;  ///< the target object
  bool fingertip = false;
  std::string name;
  /// Creation order (the scene's objects, then the robot's). FCL's
  /// narrowphase may answer a touching pair differently in the two argument
  /// orders (cylinder against cylinder at distance 0), so every check passes
  /// the pair in this order: the broadphase and the sphere tier's pairs
  /// then get the same answer.
  std::size_t order = 0;
  /// A primitive's CollisionShape::Type and size, for provablyApart; -1 for
  /// a mesh.
  int primitive_type = -1;
  Eigen::Vector3d primitive_size = Eigen::Vector3d::Zero();
  /// A mesh's bounding box, placed with it (owned by the scene): its
  /// distance bounds the mesh's from below at a fraction of the cost.
  const fcl::CollisionObjectd* bound = nullptr;
  /// The space beside the target no camera saw free (withHiddenSide): it
  /// touches the target by construction, which is no collision.
  bool beside_target = false;
};

/// `type`: a CollisionShape::Type or Obstacle::Type value (they agree, see
/// scene.h) other than kMesh.
Geometry primitive(int type, const Eigen::Vector3d& size);

/// A cloud's occupied voxels as FCL's octree (octomap): a leaf's box is
/// the voxel's.
Geometry cloudGeometry(const VoxelCloud& cloud);
/// Two opposite corners of the box around a cloud's occupied voxels.
Vertices cloudCorners(const VoxelCloud& cloud);

/// A mesh as FCL's bounding-volume hierarchy (OBBRSS).
Geometry meshGeometry(const TriangleMesh& mesh);

/// The grasp rule's view of the target: where it is and how deep a
/// fingertip may be inside it.
struct GraspContactRule {
  const ObjectSurface* surface = nullptr;
  Eigen::Isometry3d worldToObject = Eigen::Isometry3d::Identity();
  double maxPenetration = 0.0;
};

struct QueryData {
  const RobotModel* model = nullptr;
  /// The grasp rule: a fingertip link may be inside the target by at most
  /// `rule.maxPenetration` (exact signed distance); everything else as
  /// the full rule.
  bool allowFingertipContact = false;
  GraspContactRule rule;
  bool target = true;     ///< contacts with the target count (CollisionRequest::target)
  bool obstacles = true;  ///< contacts with the obstacles count (CollisionRequest::obstacles)
  bool self = true;       ///< contacts between robot links count (CollisionRequest::self)
  /// m: collideCallback counts a pair nearer than this as a contact (FCL's
  /// distance; 0: only a contact counts).
  double clearance = 0.0;
  bool collision = false;
  CollisionPair pair;
  double distance = std::numeric_limits<double>::infinity();
  const void* query = nullptr;  ///< one object against the environment: its tag comes first
  /// Distance queries: a mesh whose bounding box is at least this far (m)
  /// counts with the box's distance, a lower bound, instead of its own
  /// (0: always exact).
  double exactWithin = 0.0;
};

/// Full rule: the broadphase's collision callback; stops at the first
/// contact (the robot's part named first in QueryData::pair). Under
/// QueryData::allowFingertipContact a fingertip shape may be inside the
/// target by at most the rule's depth. With QueryData::clearance a pair
/// nearer than it counts as a contact.
bool collideCallback(Object* o1, Object* o2, void* raw);

/// The smallest distance of a robot link from anything (QueryData::distance).
bool distanceCallback(Object* o1, Object* o2, void* raw, double& minimum);
/// distanceCallback for one robot object against the environment's
/// manager, which passes its own object first: the robot's is put first.
bool objectDistanceCallback(Object* o1, Object* o2, void* raw, double& minimum);

/// The target against the obstacles.
bool targetCallback(Object* o1, Object* o2, void* raw);

/// One object (QueryData::query) against the environment: any collision
/// except with the target object; the pair names the object first.
bool obstacleCallback(Object* o1, Object* o2, void* raw);

/// The environment as the sphere tier sees it, in the scene's order:
/// obstacles, then the target. A mesh becomes its bounding box, refined by
/// its distance grid when it has one.
std::vector<SphereTier::Item> sphereTierItems(const Scene& scene, const db::ObjectGeometry* target);

}  // namespace hfts::robot::fcl_query
