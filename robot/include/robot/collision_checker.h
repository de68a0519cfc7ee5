#pragma once
// Collision checking of the robot against a scene and itself (FCL 0.7):
// the scene prepared once and shared (CollisionScene), each thread's
// working state apart (CollisionChecker), queries that say what counts
// (CollisionRequest).

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "hfts_db/object_database.h"
#include "robot/collision_model.h"
#include "robot/collision_pair.h"
#include "robot/configuration_metric.h"
#include "robot/robot_model.h"
#include "robot/scene.h"

namespace hfts::robot {

class ObjectSurface;  // object_surface.h

/// How deep (m) a fingertip link may be inside the target under the grasp
/// rule, by default: the depth a fingertip pad's rubber takes when it
/// presses (CollisionChecker::setMaxPenetration).
inline constexpr double kDefaultMaxPenetration = 0.001;

/// The clearance rule (CollisionScene) holds two links to a scene's
/// clearance only when more than this many moving joints lie between them:
/// nearer links (a wrist's) lie close by the arm's build, whatever the path.
inline constexpr int kClearanceJointsApart = 2;

/// The bounding-volume hierarchy of a triangle mesh for collision checks
/// (FCL's OBBRSS BVH). Building it takes about 2.5 ms per thousand
/// triangles, so a mesh used by many plans is built once and shared by
/// their checkers, from any thread: queries only read it.
class CollisionMesh {
 public:
  explicit CollisionMesh(const TriangleMesh& mesh);
  ~CollisionMesh();
  CollisionMesh(const CollisionMesh&) = delete;
  CollisionMesh& operator=(const CollisionMesh&) = delete;

 private:
  friend class CollisionScene;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Which contacts a collision query counts (FCL's request, for our rules).
struct CollisionRequest {
  /// kGraspRule: a fingertip link may touch the target object and be
  /// inside it by at most maxPenetration(), measured by the exact signed
  /// distance to the target's mesh (ObjectSurface); every other link must
  /// stay clear of the target, and every link, fingertips included, clear
  /// of the obstacles (the support too). kStrict: any contact counts.
  enum class Rule { kStrict, kGraspRule };
  Rule rule = Rule::kStrict;
  bool target = true;     ///< the target object counts
  bool self = true;       ///< the robot's links against each other count
  bool obstacles = true;  ///< the obstacles (every object but the target) count
  /// Keep the scene's clearance (CollisionScene::clearance; nothing more
  /// when it has none): a pair nearer than it counts as a contact, under
  /// the clearance rule (CollisionScene).
  bool clearance = true;

  /// The grasp rule with everything else counted.
  static CollisionRequest grasp() { return {Rule::kGraspRule, true, true, true}; }
  /// The obstacles only: neither the target nor the robot's own links.
  static CollisionRequest obstaclesOnly() { return {Rule::kStrict, false, false, true}; }
  /// The target only: neither the obstacles nor the robot's own links.
  static CollisionRequest targetOnly() { return {Rule::kStrict, true, false, false}; }
};

/// One robot in one scene, prepared for collision checks and read-only
/// once built (share it between threads; each thread checks with its own
/// CollisionChecker over it): the obstacles and the target as FCL objects
/// in a broadphase manager, the sphere tier's compiled scene (which robot
/// links can touch what at all), the target's exact surface. Also the
/// queries that do not move the robot.
///
/// A scene may keep a clearance (docs/collision.md "Clearance"): its
/// checks (CollisionRequest::clearance) then count a link nearer than it
/// to what the request counts as a contact (FCL's distance, behind a
/// sphere tier grown by the clearance), under the clearance rule:
/// - every link that moves keeps it from the obstacles, and every link but
///   the hand's (the palm and what moves with a hand DoF) from the target;
/// - two links keep it from each other unless both are the hand's (an
///   open hand's fingers lie close) or at most kClearanceJointsApart
///   moving joints lie between them;
/// - under the grasp rule the hand's links need only be free of the
///   obstacles too (the fingers close on an object that stands on them);
/// - a link that never moves need only be free.
class CollisionScene {
 public:
  /// `target` (may be null: no target object) is placed at
  /// scene.target_pose. `targetMesh`, when given, is the prebuilt hierarchy
  /// of target's mesh (else it is built here); `targetSurface`, when given,
  /// the target's ObjectSurface (else built here when the grasp rule first
  /// needs it). `clearance` (m) is what the scene's checks keep (0: none).
  /// The model, target, targetMesh and targetSurface must outlive the
  /// scene. Throws InvalidArgument ("clearance") for a negative or
  /// non-finite clearance.
  CollisionScene(const CollisionModel& model, const Scene& scene, const db::ObjectGeometry* target,
                 const CollisionMesh* targetMesh = nullptr,
                 const ObjectSurface* targetSurface = nullptr, double clearance = 0.0);
  ~CollisionScene();
  CollisionScene(const CollisionScene&) = delete;
  CollisionScene& operator=(const CollisionScene&) = delete;

  const CollisionModel& model() const;
  const Scene& scene() const;
  /// The clearance the scene's checks keep (m; 0: none).
  double clearance() const;

  /// True when the target object intersects an obstacle (a scene that
  /// places the object inside something); the space beside it that its
  /// views could not see free (withHiddenSide) does not count.
  bool targetTouchesObstacles(CollisionPair* pair = nullptr) const;

  /// True when a sphere (world frame) intersects an obstacle (touching
  /// counts; the target object is not an obstacle); `pair` gets "sphere"
  /// and the obstacle. For asking where a fingertip fits
  /// (grasp/contact_mask.h). Throws InvalidArgument for a radius that is
  /// not > 0 or a non-finite centre.
  bool sphereTouchesObstacles(const Eigen::Vector3d& center, double radius,
                              CollisionPair* pair = nullptr) const;

 private:
  friend class CollisionChecker;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Checks configurations of one robot in one scene: one thread's working
/// state (the robot's FCL objects, forward kinematics, scratch, counters)
/// over a shared CollisionScene. Robot links are the URDF primitives,
/// obstacles FCL primitives or BVH meshes, the target object its mesh from
/// the database; in front of FCL, a conservative sphere tier
/// (setSphereTier). Not thread-safe: give each thread its own checker,
/// over one scene.
class CollisionChecker {
 public:
  /// Throws InvalidArgument ("scene") for a null scene.
  explicit CollisionChecker(std::shared_ptr<const CollisionScene> scene);
  /// A checker over a scene of its own (CollisionScene's arguments).
  CollisionChecker(const CollisionModel& model, const Scene& scene,
                   const db::ObjectGeometry* target, const CollisionMesh* targetMesh = nullptr,
                   const ObjectSurface* targetSurface = nullptr);
  ~CollisionChecker();
  CollisionChecker(const CollisionChecker&) = delete;
  CollisionChecker& operator=(const CollisionChecker&) = delete;

  /// True when the robot at q touches what `request` counts: obstacles,
  /// the target object (under the request's rule) and itself (except
  /// disabled link pairs). q must be valid (numDofs values).
  bool inCollision(const Eigen::VectorXd& q, const CollisionRequest& request,
                   CollisionPair* pair = nullptr);
  /// Everything counts, strictly.
  bool inCollision(const Eigen::VectorXd& q, CollisionPair* pair = nullptr) {
    return inCollision(q, CollisionRequest{}, pair);
  }
  /// Each of `count` configurations checked as inCollision checks one,
  /// the sphere tier testing them a batch at a time: colliding[i] says
  /// whether states[i] collides. Returns how many collide.
  std::size_t inCollision(const Eigen::VectorXd* const* states, std::size_t count,
                          const CollisionRequest& request, bool* colliding);

  /// The grasp rule's allowed fingertip depth in the target (m;
  /// kDefaultMaxPenetration unless set). Throws InvalidArgument
  /// ("max_penetration") for a negative or non-finite depth.
  void setMaxPenetration(double depth);
  double maxPenetration() const;

  /// True when the hand alone (the palm and every link that moves with a
  /// hand DoF, robot_model.h isHandLink), with its palm at `palm` (world
  /// frame) and its joints at `hand` (numHandDofs values), touches what
  /// `request` counts (self: the hand's links against each other). Asks
  /// where a hand fits before any arm IK (strictly: the scene's clearance
  /// is not kept); checkCount() does not change.
  /// Throws InvalidArgument for a hand of the wrong size or a non-finite
  /// value.
  bool handInCollision(const Eigen::Isometry3d& palm, const Eigen::VectorXd& hand,
                       const CollisionRequest& request, CollisionPair* pair = nullptr);

  /// Smallest distance between the robot and the environment including the
  /// target object (m); 0 when in collision.
  double clearance(const Eigen::VectorXd& q);
  /// For each of `links`, the smallest distance (m) between its shapes and
  /// the environment as `request` counts it (the obstacles, the target),
  /// in `distances` (same order; infinity for a link without shapes or
  /// nothing counted, 0 where it touches).
  /// With `exactWithin` > 0 (m), a mesh (the target, a mesh obstacle)
  /// whose bounding box is at least that far from a link counts with the
  /// box's distance, a lower bound, instead of its own: distances below
  /// `exactWithin` are exact, the others may be lower bounds.
  void linkClearances(const Eigen::VectorXd& q, const std::vector<int>& links,
                      std::vector<double>& distances, const CollisionRequest& request = {},
                      double exactWithin = 0.0);
  /// For each link pair of `pairs`, the smallest distance (m) between their
  /// shapes in `distances` (same order; 0 where they touch), whether or not
  /// the config disables the pair.
  void pairClearances(const Eigen::VectorXd& q, const std::vector<std::pair<int, int>>& pairs,
                      std::vector<double>& distances);
  /// Smallest distance between two of the robot's links that may collide
  /// (pairs not disabled in the config) (m); 0 when two of them touch.
  double selfClearance(const Eigen::VectorXd& q);

  /// Checks the straight segment from a to b (a is assumed valid) at
  /// `resolution` in the weighted metric of Eq. (3): every intermediate
  /// state and b itself (b first, then the others in bisection order).
  bool isMotionValid(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double resolution,
                     const CollisionRequest& request = {}, CollisionPair* pair = nullptr);

  /// Checks the polyline waypoints[0] -> waypoints[1] -> ... segment by
  /// segment as isMotionValid does (waypoints[0] is assumed valid), with all
  /// their states in one stream, so that the sphere tier tests them a batch
  /// at a time. Returns the number of leading segments that are valid:
  /// waypoints.size() - 1 when all are (0 for fewer than two waypoints).
  /// Counts states as checking the segments one after another would.
  std::size_t validSegments(const std::vector<Eigen::VectorXd>& waypoints, double resolution,
                            const CollisionRequest& request = {}, CollisionPair* pair = nullptr);
  /// The same for the polyline *waypoints[0] -> ... -> *waypoints[count - 1].
  std::size_t validSegments(const Eigen::VectorXd* const* waypoints, std::size_t count,
                            double resolution, const CollisionRequest& request = {},
                            CollisionPair* pair = nullptr);

  /// The Eq. (3) metric of isMotionValid's resolution: the robot's DoF
  /// weights unless changed. Shared with the OMPL state space made on this
  /// checker (makeSpaceInformation), so a weight set on either is set on both.
  ConfigurationMetric& metric() const;
  std::shared_ptr<ConfigurationMetric> sharedMetric() const;

  const RobotModel& model() const;
  const CollisionScene& scene() const;

  /// Configurations checked so far (every query above counts each robot
  /// placement it tests once).
  std::uint64_t checkCount() const;

  /// Two tiers (default): inCollision and its variants first test the
  /// robot's sphere model (CollisionModel::spheres) against the scene's
  /// primitives, the meshes' bounding boxes and itself, and ask FCL only
  /// about the pairs (link and obstacle, or two links) whose spheres touch.
  /// The spheres cover the links, so the answer is FCL's either way; false
  /// gives the FCL-only checker (broadphase over everything), to compare.
  /// A check that keeps a clearance always goes through the (grown) tier.
  void setSphereTier(bool enabled);
  bool sphereTier() const;
  /// Of checkCount(), the checks the sphere tier settled alone (free); a
  /// check whose touching pairs the request all leaves out counts as
  /// settled.
  std::uint64_t sphereSettledCount() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hfts::robot
