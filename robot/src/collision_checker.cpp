// FCL stays in the robot library's .cpp files: its headers are
// template-heavy. The FCL callbacks and geometry are in fcl_query.h.
#include "robot/collision_checker.h"

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "collision_scene.h"
#include "core/invalid_argument.h"
#include "fcl_query.h"
#include "robot/kinematics.h"
#include "robot/object_surface.h"
#include "shape_separation.h"
#include "sphere_tier.h"

namespace hfts::robot {

using fcl_query::collideCallback;
using fcl_query::distanceCallback;
using fcl_query::objectDistanceCallback;
using fcl_query::QueryData;

/// How far apart (m) a separating axis must prove two primitives before
/// FCL is skipped: far above the tolerance of FCL's narrowphase (1e-6 in
/// GJK), so FCL would call every such pair free.
constexpr double kApartGap = 1e-4;

namespace {

/// Where a segment of n steps checks its states, as fractions k / n of
/// the way, in check order: its end first, then the states between in
/// breadth-first bisection order (as OMPL's DiscreteMotionValidator): a
/// colliding segment is usually found after a few checks, not halfway.
/// Those of up to kKeptUpTo steps are kept for the thread's lifetime (a
/// tree's extensions repeat their step counts, and a thread that plans
/// again meets the same counts); a longer one is valid until the
/// thread's next call.
const std::vector<double>& checkOrder(int n) {
  constexpr std::size_t kKeptUpTo = 1024;  // at most 4.2 MB of kept orders a thread
  thread_local std::vector<std::vector<double>> kept(kKeptUpTo + 1);
  thread_local std::vector<double> longer;
  const auto slot = static_cast<std::size_t>(n);
  if (slot <= kKeptUpTo && !kept[slot].empty()) return kept[slot];
  // Made whole before it is kept: a kept order is never a partial one.
  std::vector<double> order;
  order.reserve(slot);
  order.push_back(1.0);
  std::vector<std::pair<int, int>> open{{0, n}};  // ranges still unchecked, a FIFO
  open.reserve(2 * slot + 1);
  for (std::size_t next = 0; next < open.size(); ++next) {
    const auto [from, to] = open[next];
    if (to - from < 2) continue;
    const int mid = (from + to) / 2;
    order.push_back(static_cast<double>(mid) / n);
    open.emplace_back(from, mid);
    open.emplace_back(mid, to);
  }
  std::vector<double>& place = slot <= kKeptUpTo ? kept[slot] : longer;
  place.swap(order);
  return place;
}

}  // namespace

struct CollisionChecker::Impl {
  const std::shared_ptr<const CollisionScene> owner;
  const CollisionScene::Impl& shared;
  const RobotModel& model;
  const Eigen::Isometry3d base;
  const SphereTier& tier;  // first tier
  RobotObjects robot;
  LinkPoses poses;
  bool useTier = true;
  std::uint64_t checks = 0, settledBySpheres = 0;
  std::shared_ptr<ConfigurationMetric> metric;  // Eq. (3)
  double maxPenetration = kDefaultMaxPenetration;
  std::vector<LinkPoses> lanePoses;  // scratch: the poses of a batch's configurations
  std::vector<float> tierScratch;    // scratch: a batch for the sphere tier
  // Scratch of validSegments, a batch of states in check order: state i
  // of segment stateSegments[i] lies at stateAlong[i] of the way from
  // *stateFrom[i] to *stateTo[i]; motionStates[i] holds it in double
  // precision once FCL asked for it (SegmentStates).
  std::vector<std::size_t> stateSegments;
  std::vector<const Eigen::VectorXd*> stateFrom, stateTo;
  std::vector<double> stateAlong;
  std::vector<Eigen::VectorXd> motionStates;
  std::vector<const Eigen::VectorXd*> waypointPointers;  // scratch of the public validSegments

  explicit Impl(std::shared_ptr<const CollisionScene> scene)
      : owner(std::move(scene)),
        shared(*owner->impl_),
        model(shared.model.robot),
        base(shared.scene.robot_base),
        tier(*shared.tier),
        robot(model, shared.tags.size()),
        metric(std::make_shared<ConfigurationMetric>(model.dofWeights())) {}

  /// The environment's manager, for FCL's manager-against-manager
  /// queries, which take it by pointer but only read it.
  fcl::DynamicAABBTreeCollisionManagerd* environment() const {
    return const_cast<fcl::DynamicAABBTreeCollisionManagerd*>(&shared.environment);
  }

  /// A query that counts what `request` counts.
  QueryData queryData(const CollisionRequest& request) {
    QueryData data;
    data.model = &model;
    data.target = request.target;
    data.obstacles = request.obstacles;
    data.self = request.self;
    data.allowFingertipContact = request.rule == CollisionRequest::Rule::kGraspRule;
    if (data.allowFingertipContact)
      data.rule = {shared.surface(), shared.scene.target_pose.inverse(), maxPenetration};
    return data;
  }

  void place(const Eigen::VectorXd& q) {
    forwardKinematics(model, q, poses);
    robot.place(base, poses);
  }

  bool collide(const Eigen::VectorXd& q, const CollisionRequest& request, CollisionPair* pair) {
    const Eigen::VectorXd* state = &q;
    return firstCollision(PointedStates{&state}, 1, request, pair) == 0;
  }

  /// Configurations a query reads: at(i) is configuration i, and
  /// touchingPairs hands configurations begin .. begin + n - 1 to the
  /// sphere tier.
  struct PointedStates {
    const Eigen::VectorXd* const* states;
    const Eigen::VectorXd& at(std::size_t i) const { return *states[i]; }
    template <typename Visit>
    void touchingPairs(const SphereTier& spheres, std::size_t begin, std::size_t n,
                       std::vector<float>& scratch, Visit& visit) const {
      spheres.forEachTouchingPair(states + begin, n, scratch, visit);
    }
  };

  /// The states of a validSegments batch (one batch: touchingPairs is
  /// asked for begin 0 and all of them): written in the tier's batch
  /// layout into tierScratch as they were made, and in double precision
  /// only when FCL needs one.
  struct SegmentStates {
    Impl& impl;
    const Eigen::VectorXd& at(std::size_t i) const {
      Eigen::VectorXd& q = impl.motionStates[i];
      q.resize(impl.stateFrom[i]->size());
      interpolate(*impl.stateFrom[i], *impl.stateTo[i], impl.stateAlong[i], q.data());
      return q;
    }
    template <typename Visit>
    void touchingPairs(const SphereTier& spheres, std::size_t, std::size_t n,
                       std::vector<float>& scratch, Visit& visit) const {
      spheres.forEachTouchingPairWritten(n, scratch, visit);
    }
  };

  /// a + (b - a) t: the one formula of a segment's states, for the sphere
  /// tier's single precision and for FCL's double.
  static double between(double a, double b, double t) { return a + (b - a) * t; }
  static void interpolate(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double t,
                          double* out) {
    for (Eigen::Index d = 0; d < a.size(); ++d) out[d] = between(a[d], b[d], t);
  }

  /// The index of the first of `states` (in their order) that collides, or
  /// -1. Counts the states up to that one (all of them when none collides),
  /// as checking them one by one would: the sphere tier tests a batch at a
  /// time, FCL then takes the batch's configurations in order.
  template <typename States>
  long firstCollision(const States& states, std::size_t count, const CollisionRequest& request,
                      CollisionPair* pair) {
    QueryData data = queryData(request);
    const double margin = request.clearance ? shared.clearance : 0.0;
    if (!useTier && margin <= 0.0) {
      for (std::size_t i = 0; i < count; ++i) {
        ++checks;
        place(states.at(i));
        robot.manager().collide(environment(), &data, collideCallback);
        if (!data.collision && request.self)
          robot.manager().collide(&data, collideCallback);  // self-collision
        if (data.collision) return found(static_cast<long>(i), data, pair);
      }
      return -1;
    }
    const SphereTier& spheres = margin > 0.0 ? *shared.clearanceTier : tier;
    const bool graspRule = request.rule == CollisionRequest::Rule::kGraspRule;
    const std::size_t batch = spheres.batchSize();
    lanePoses.resize(batch);
    for (std::size_t begin = 0; begin < count; begin += batch) {
      const std::size_t n = std::min(batch, count - begin);
      // FCL takes each touching pair's configurations in order; after a
      // collision at lane L only the lanes before it still matter.
      std::uint32_t placed = 0, touched = 0;
      std::size_t first = n;
      const auto visit = [&](const SphereTier::Pair& p, std::uint32_t lanes) -> std::uint32_t {
        if (!counts(p, request)) return (1u << first) - 1u;
        touched |= lanes;
        data.clearance = margin > 0.0 && keepsClearance(p, graspRule) ? margin : 0.0;
        for (std::size_t lane = 0; lane < first; ++lane) {
          const std::uint32_t bit = 1u << lane;
          if ((lanes & bit) == 0) continue;
          if ((placed & bit) == 0) {
            forwardKinematics(model, states.at(begin + lane), lanePoses[lane]);
            placed |= bit;
          }
          if (pairCollides(p, lanePoses[lane], data)) first = lane;
        }
        return (1u << first) - 1u;
      };
      states.touchingPairs(spheres, begin, n, tierScratch, visit);
      const std::size_t checked = std::min(first + 1, n);
      checks += checked;
      for (std::size_t lane = 0; lane < checked; ++lane)
        if (((touched >> lane) & 1u) == 0) ++settledBySpheres;
      if (first < n) return found(static_cast<long>(begin + first), data, pair);
    }
    return -1;
  }

  /// Whether a pair the sphere tier names keeps the scene's clearance
  /// (the clearance rule, CollisionScene).
  bool keepsClearance(const SphereTier::Pair& p, bool graspRule) const {
    if (p.other_link >= 0) return shared.keepsClearance(p.link, p.other_link);
    return shared.keepsClearance(p.link, tier.isTarget(p.item), graspRule);
  }

  /// Whether the request counts a pair the sphere tier names.
  bool counts(const SphereTier::Pair& p, const CollisionRequest& request) const {
    if (p.other_link >= 0) return request.self;
    return tier.isTarget(p.item) ? request.target : request.obstacles;
  }

  /// The number of leading segments of the polyline points[0] -> ... ->
  /// points[count - 1] whose states (every state at `resolution` and the
  /// end, points[0] assumed valid) are free; all states in one stream,
  /// made a batch at a time as the check reaches them (a colliding
  /// segment usually stops the stream early: half the states a plan's
  /// checks would make are never checked).
  std::size_t validSegments(const Eigen::VectorXd* const* points, std::size_t count,
                            double resolution, const CollisionRequest& request,
                            CollisionPair* pair) {
    if (!(resolution > 0.0)) throw InvalidArgument("resolution", "must be > 0");
    const auto dofs = static_cast<std::size_t>(model.numDofs());
    for (std::size_t i = 0; i < count; ++i)
      if (static_cast<std::size_t>(points[i]->size()) != dofs)
        throw InvalidArgument("waypoints", "waypoint " + std::to_string(i) + " has " +
                                               std::to_string(points[i]->size()) +
                                               " values, the robot " + std::to_string(dofs) +
                                               " DoF");
    if (count < 2) return 0;
    // The tier firstCollision tests with (its batch layout).
    const SphereTier& spheres =
        request.clearance && shared.clearance > 0.0 ? *shared.clearanceTier : tier;
    const std::size_t batch = spheres.batchSize();
    if (motionStates.size() < batch) motionStates.resize(batch);
    stateSegments.resize(batch);
    stateFrom.resize(batch);
    stateTo.resize(batch);
    stateAlong.resize(batch);
    spheres.prepareBatch(tierScratch);
    // The segment being made, from points[segment] to points[segment + 1]:
    // its steps in check order and the next of them.
    std::size_t segment = 0, next = 0;
    const std::vector<double>* order = nullptr;
    for (;;) {
      std::size_t n = 0;
      for (; n < batch && segment + 1 < count; ++n) {
        const Eigen::VectorXd& a = *points[segment];
        const Eigen::VectorXd& b = *points[segment + 1];
        if (order == nullptr) {
          order = &checkOrder(
              std::max(1, static_cast<int>(std::ceil(metric->distance(a, b) / resolution))));
          next = 0;
        }
        const double along = (*order)[next];
        for (std::size_t d = 0; d < dofs; ++d) {
          const auto k = static_cast<Eigen::Index>(d);
          tierScratch[d * batch + n] = static_cast<float>(between(a[k], b[k], along));
        }
        stateSegments[n] = segment;
        stateFrom[n] = &a;
        stateTo[n] = &b;
        stateAlong[n] = along;
        if (++next == order->size()) {
          order = nullptr;
          ++segment;
        }
      }
      if (n == 0) return count - 1;
      const long first = firstCollision(SegmentStates{*this}, n, request, pair);
      if (first >= 0) return stateSegments[static_cast<std::size_t>(first)];
    }
  }

  static long found(long index, const QueryData& data, CollisionPair* pair) {
    if (pair != nullptr) *pair = data.pair;
    return index;
  }

  /// FCL on the shapes of one pair the sphere tier found touching, the
  /// robot at `at`: a link-item pair places the link's shapes as it
  /// reaches them, a link pair both links' shapes first.
  bool pairCollides(const SphereTier::Pair& p, const LinkPoses& at, QueryData& data) {
    if (p.other_link < 0) {
      // Shape by shape, each placed when reached: nine in ten pairs the
      // spheres send collide, most before the link's last shape.
      Object& item = *shared.environmentObjects[p.item];
      for (const std::size_t i : robot.linkObjects[static_cast<std::size_t>(p.link)])
        if (shapesCollide(placedShape(i, at), item, data)) return true;
      return false;
    }
    const std::vector<std::size_t>& shapes = placedLink(p.link, at);
    const std::vector<std::size_t>& others = placedLink(p.other_link, at);
    for (const std::size_t i : shapes)
      for (const std::size_t j : others)
        if (shapesCollide(*robot.objects[i], *robot.objects[j], data)) return true;
    return false;
  }

  /// As FCL's broadphase does it: the narrowphase only for overlapping
  /// bounding boxes (touching ones included), so both modes agree. Two
  /// primitives that a separating axis proves more than kApartGap apart
  /// skip the narrowphase too: FCL calls them free, and its GJK on
  /// cylinders costs microseconds (most pairs the spheres send are a
  /// hand's neighbouring fingers, close but apart). With a clearance to
  /// keep (QueryData::clearance) FCL's distance decides, unless the axis
  /// proves the pair farther apart than the clearance.
  static bool shapesCollide(Object& a, Object& b, QueryData& data) {
    if (data.clearance > 0.0)
      return !provablyApart(a, b, data.clearance + kApartGap) && collideCallback(&a, &b, &data);
    return a.getAABB().overlap(b.getAABB()) && !provablyApart(a, b, kApartGap) &&
           collideCallback(&a, &b, &data);
  }

  static bool provablyApart(const Object& a, const Object& b, double gap) {
    const Tag& tagA = *static_cast<const Tag*>(a.getUserData());
    const Tag& tagB = *static_cast<const Tag*>(b.getUserData());
    if (tagA.primitive_type < 0 || tagB.primitive_type < 0) return false;
    const auto placed = [](const Object& o, const Tag& t) {
      return PlacedShape{t.primitive_type, t.primitive_size, o.getRotation(), o.getTranslation()};
    };
    return robot::provablyApart(placed(a, tagA), placed(b, tagB), gap);
  }

  /// The link's objects, moved to its pose in `at`.
  const std::vector<std::size_t>& placedLink(int link, const LinkPoses& at) {
    const auto l = static_cast<std::size_t>(link);
    for (const std::size_t i : robot.linkObjects[l]) placedShape(i, at);
    return robot.linkObjects[l];
  }

  /// Object i, moved to its link's pose in `at`.
  Object& placedShape(std::size_t i, const LinkPoses& at) {
    const auto& [link, origin] = robot.shapes[i];
    const Eigen::Isometry3d pose = base * at[static_cast<std::size_t>(link)] * origin;
    Object& object = *robot.objects[i];
    object.setTransform(pose.linear(), pose.translation());
    object.computeAABB();
    return object;
  }
};

CollisionChecker::CollisionChecker(std::shared_ptr<const CollisionScene> scene)
    : impl_(scene ? std::make_unique<Impl>(std::move(scene))
                  : throw InvalidArgument("scene", "a checker needs a collision scene")) {}

CollisionChecker::CollisionChecker(const CollisionModel& model, const Scene& scene,
                                   const db::ObjectGeometry* target,
                                   const CollisionMesh* targetMesh,
                                   const ObjectSurface* targetSurface)
    : CollisionChecker(std::make_shared<const CollisionScene>(model, scene, target, targetMesh,
                                                              targetSurface)) {}

CollisionChecker::~CollisionChecker() = default;

const RobotModel& CollisionChecker::model() const {
  return impl_->model;
}

const CollisionScene& CollisionChecker::scene() const {
  return *impl_->owner;
}

bool CollisionChecker::inCollision(const Eigen::VectorXd& q, const CollisionRequest& request,
                                   CollisionPair* pair) {
  return impl_->collide(q, request, pair);
}

std::size_t CollisionChecker::inCollision(const Eigen::VectorXd* const* states, std::size_t count,
                                          const CollisionRequest& request, bool* colliding) {
  // Up to the first collision, the states are free; the search goes on
  // after it.
  std::size_t collisions = 0;
  for (std::size_t begin = 0; begin < count;) {
    const long first =
        impl_->firstCollision(Impl::PointedStates{states + begin}, count - begin, request, nullptr);
    const std::size_t free = first < 0 ? count - begin : static_cast<std::size_t>(first);
    std::fill(colliding + begin, colliding + begin + free, false);
    begin += free;
    if (first >= 0) {
      colliding[begin++] = true;
      ++collisions;
    }
  }
  return collisions;
}

void CollisionChecker::setMaxPenetration(double depth) {
  if (!(depth >= 0.0) || !std::isfinite(depth))
    throw InvalidArgument("max_penetration", "must be a finite number >= 0 (m)");
  impl_->maxPenetration = depth;
}

double CollisionChecker::maxPenetration() const {
  return impl_->maxPenetration;
}

bool CollisionChecker::handInCollision(const Eigen::Isometry3d& palm, const Eigen::VectorXd& hand,
                                       const CollisionRequest& request, CollisionPair* pair) {
  const RobotModel& model = impl_->model;
  if (hand.size() != model.numHandDofs() || !hand.allFinite() || !palm.matrix().allFinite())
    throw InvalidArgument("hand", "needs a finite palm pose and " +
                                      std::to_string(model.numHandDofs()) + " finite joint values");
  // The hand's objects (the palm and every link that moves with a hand
  // DoF) placed so that the palm is at `palm`; every robot query places
  // the objects before it reads them.
  Eigen::VectorXd q = model.home();
  q.tail(model.numHandDofs()) = hand;
  forwardKinematics(model, q, impl_->poses);
  const Eigen::Isometry3d toWorld =
      palm * impl_->poses[static_cast<std::size_t>(model.palmLink())].inverse();
  std::vector<std::size_t> placed;
  for (std::size_t i = 0; i < impl_->robot.objects.size(); ++i) {
    const auto& [link, origin] = impl_->robot.shapes[i];
    if (!model.isHandLink(link)) continue;
    Object& object = *impl_->robot.objects[i];
    const Eigen::Isometry3d pose = toWorld * impl_->poses[static_cast<std::size_t>(link)] * origin;
    object.setTransform(pose.linear(), pose.translation());
    object.computeAABB();
    placed.push_back(i);
  }
  // Each pair in creation order (the scene's object first), as
  // inCollision passes it: the two give one answer for touching shapes.
  QueryData data = impl_->queryData(request);
  for (std::size_t k = 0; k < placed.size() && !data.collision; ++k) {
    Object& object = *impl_->robot.objects[placed[k]];
    impl_->shared.environment.collide(&object, &data, collideCallback);
    for (std::size_t l = k + 1; l < placed.size() && !data.collision && request.self; ++l)
      Impl::shapesCollide(object, *impl_->robot.objects[placed[l]], data);
  }
  if (data.collision && pair != nullptr) *pair = data.pair;
  return data.collision;
}

std::uint64_t CollisionChecker::checkCount() const {
  return impl_->checks;
}

void CollisionChecker::setSphereTier(bool enabled) {
  impl_->useTier = enabled;
  // FCL alone asks the broadphase: made now, before the first query moves
  // the robot, so that its tree grows as it always has.
  if (!enabled) impl_->robot.manager();
}

bool CollisionChecker::sphereTier() const {
  return impl_->useTier;
}

std::uint64_t CollisionChecker::sphereSettledCount() const {
  return impl_->settledBySpheres;
}

double CollisionChecker::clearance(const Eigen::VectorXd& q) {
  if (impl_->collide(q, {}, nullptr)) return 0.0;
  impl_->place(q);  // the sphere tier may have left the broadphase where it was
  QueryData data;
  data.model = &impl_->model;
  impl_->robot.manager().distance(impl_->environment(), &data, distanceCallback);
  return data.distance;
}

void CollisionChecker::linkClearances(const Eigen::VectorXd& q, const std::vector<int>& links,
                                      std::vector<double>& distances,
                                      const CollisionRequest& request, double exactWithin) {
  distances.assign(links.size(), std::numeric_limits<double>::infinity());
  if (links.empty()) return;
  impl_->place(q);
  for (std::size_t k = 0; k < links.size(); ++k)
    for (const std::size_t object :
         impl_->robot.linkObjects.at(static_cast<std::size_t>(links[k]))) {
      QueryData data;
      data.model = &impl_->model;
      data.target = request.target;
      data.obstacles = request.obstacles;
      data.exactWithin = exactWithin;
      impl_->environment()->distance(impl_->robot.objects[object].get(), &data,
                                     objectDistanceCallback);
      distances[k] = std::min(distances[k], data.distance);
    }
}

void CollisionChecker::pairClearances(const Eigen::VectorXd& q,
                                      const std::vector<std::pair<int, int>>& pairs,
                                      std::vector<double>& distances) {
  distances.assign(pairs.size(), std::numeric_limits<double>::infinity());
  if (pairs.empty()) return;
  impl_->place(q);
  const RobotObjects& robot = impl_->robot;
  for (std::size_t k = 0; k < pairs.size(); ++k)
    for (const std::size_t i : robot.linkObjects.at(static_cast<std::size_t>(pairs[k].first)))
      for (const std::size_t j : robot.linkObjects.at(static_cast<std::size_t>(pairs[k].second))) {
        fcl::DistanceRequestd request;
        fcl::DistanceResultd result;
        fcl::distance(robot.objects[std::min(i, j)].get(), robot.objects[std::max(i, j)].get(),
                      request, result);
        distances[k] = std::min(distances[k], std::max(0.0, result.min_distance));
      }
}

double CollisionChecker::selfClearance(const Eigen::VectorXd& q) {
  impl_->place(q);
  QueryData data;
  data.model = &impl_->model;
  impl_->robot.manager().distance(&data, distanceCallback);
  return data.distance;
}

ConfigurationMetric& CollisionChecker::metric() const {
  return *impl_->metric;
}

std::shared_ptr<ConfigurationMetric> CollisionChecker::sharedMetric() const {
  return impl_->metric;
}

bool CollisionChecker::isMotionValid(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                                     double resolution, const CollisionRequest& request,
                                     CollisionPair* pair) {
  const Eigen::VectorXd* ends[2] = {&a, &b};
  return impl_->validSegments(ends, 2, resolution, request, pair) == 1;
}

std::size_t CollisionChecker::validSegments(const std::vector<Eigen::VectorXd>& waypoints,
                                            double resolution, const CollisionRequest& request,
                                            CollisionPair* pair) {
  std::vector<const Eigen::VectorXd*>& points = impl_->waypointPointers;
  points.clear();
  for (const Eigen::VectorXd& w : waypoints) points.push_back(&w);
  return impl_->validSegments(points.data(), points.size(), resolution, request, pair);
}

std::size_t CollisionChecker::validSegments(const Eigen::VectorXd* const* waypoints,
                                            std::size_t count, double resolution,
                                            const CollisionRequest& request, CollisionPair* pair) {
  return impl_->validSegments(waypoints, count, resolution, request, pair);
}

}  // namespace hfts::robot
