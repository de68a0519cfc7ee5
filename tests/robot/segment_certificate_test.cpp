#include "robot/segment_certificate.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "bundled_objects.h"
#include "clearance_rule.h"
#include "core/invalid_argument.h"
#include "robot/kinematics.h"
#include "robot/motion_bound.h"
#include "robot_fixture.h"

namespace hfts::robot {
namespace {

const RobotModel& kr5() {
  return test::kr5Sdh();
}

const RobotModel& robotNamed(const std::string& name) {
  static std::map<std::string, RobotModel> models;
  auto it = models.find(name);
  if (it == models.end())
    it = models
             .emplace(name,
                      RobotModel::load(test::sourcePath("robots/" + name + "/" + name + ".json")))
             .first;
  return it->second;
}

Eigen::VectorXd randomConfiguration(const RobotModel& model, std::mt19937_64& rng) {
  Eigen::VectorXd q(model.numDofs());
  for (Eigen::Index d = 0; d < q.size(); ++d)
    q(d) =
        std::uniform_real_distribution<double>(model.lowerLimits()(d), model.upperLimits()(d))(rng);
  return q;
}

/// Points on the surface of a shape's bounding box (its corners and face
/// centres) in the link frame; a sphere's six poles.
std::vector<Eigen::Vector3d> shapePoints(const CollisionShape& shape) {
  std::vector<Eigen::Vector3d> points;
  const Eigen::Vector3d h = shape.type == CollisionShape::Type::kSphere
                                ? Eigen::Vector3d::Constant(shape.size.x())
                                : halfExtents(shape);
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z) {
        const int nonzero = (x != 0) + (y != 0) + (z != 0);
        if (shape.type == CollisionShape::Type::kSphere ? nonzero != 1 : nonzero == 0) continue;
        points.push_back(shape.origin * Eigen::Vector3d(x * h.x(), y * h.y(), z * h.z()));
      }
  return points;
}

/// The distance from the robot at q to what a certified transit keeps its
/// clearance from (CertifyRule::kTransit; 0 where anything touches): the
/// environment (obstacles and target) and its own links, but not a link
/// that never moves, nor two links of the hand or a few joints apart.
/// Distances beyond 5 cm may be lower bounds.
double distanceToEverything(CollisionChecker& checker, const Eigen::VectorXd& q) {
  static const test::ClearanceRule transit(kr5(), true);
  CollisionRequest strict;
  strict.clearance = false;
  return checker.inCollision(q, strict) ? 0.0 : transit.at(checker, q, false, false, 0.05).distance;
}

TEST(MotionBound, NoPointOfAnyLinkTravelsFartherThanTheBound) {
  for (const std::string name : {"kr5_sdh", "ur5e_allegro", "panda_gripper"}) {
    SCOPED_TRACE(name);
    const RobotModel& model = robotNamed(name);
    const MotionBound bound(model);
    std::mt19937_64 rng(7);
    double tightest = 0.0;  // the largest share of the bound a point used
    for (int trial = 0; trial < 60; ++trial) {
      const Eigen::VectorXd a = randomConfiguration(model, rng);
      const double scale = trial % 2 == 0 ? 0.05 : 1.0;  // short and long steps
      const Eigen::VectorXd b =
          a + scale * (randomConfiguration(model, rng) - randomConfiguration(model, rng));
      constexpr int kSteps = 64;
      std::vector<LinkPoses> poses;
      for (int i = 0; i <= kSteps; ++i)
        poses.push_back(forwardKinematics(model, a + (b - a) * (double(i) / kSteps)));
      for (std::size_t l = 0; l < model.links().size(); ++l) {
        const double limit = bound.link(static_cast<int>(l), b - a);
        for (const CollisionShape& shape : model.links()[l].shapes)
          for (const Eigen::Vector3d& point : shapePoints(shape)) {
            double travelled = 0.0;  // the polyline through the steps: <= the path's length
            for (int i = 0; i < kSteps; ++i)
              travelled += (poses[i + 1][l] * point - poses[i][l] * point).norm();
            EXPECT_LE(travelled, limit + 1e-9) << model.links()[l].name;
            if (limit > 0.0) tightest = std::max(tightest, travelled / limit);
          }
      }
    }
    // Not vacuous: some point travels a good share of its bound.
    EXPECT_GT(tightest, 0.3);
  }
}

TEST(MotionBound, NoTwoLinksComeCloserThanTheirPairBound) {
  // The distance between a point of one link and a point of another
  // changes by at most the pair bound; two fingers of a hand whose joints
  // do not move keep their distance (bound 0) while the arm moves.
  const RobotModel& model = kr5();
  const MotionBound bound(model);
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 40; ++trial) {
    const Eigen::VectorXd a = randomConfiguration(model, rng);
    const Eigen::VectorXd b = a + 0.3 * (randomConfiguration(model, rng) - a);
    const LinkPoses pa = forwardKinematics(model, a), pb = forwardKinematics(model, b);
    for (std::size_t i = 0; i < model.links().size(); ++i)
      for (std::size_t k = i + 1; k < model.links().size(); ++k) {
        if (model.links()[i].shapes.empty() || model.links()[k].shapes.empty()) continue;
        const double limit = bound.pair(static_cast<int>(i), static_cast<int>(k), b - a);
        for (const Eigen::Vector3d& p : shapePoints(model.links()[i].shapes[0]))
          for (const Eigen::Vector3d& r : shapePoints(model.links()[k].shapes[0])) {
            const double before = (pa[i] * p - pa[k] * r).norm();
            const double after = (pb[i] * p - pb[k] * r).norm();
            EXPECT_LE(std::abs(after - before), limit + 1e-9)
                << model.links()[i].name << " / " << model.links()[k].name;
          }
      }
  }
  Eigen::VectorXd armOnly = Eigen::VectorXd::Zero(model.numDofs());
  armOnly.head(model.numArmDofs()).setConstant(0.2);
  const int tipA = model.fingertips()[0].link, tipB = model.fingertips()[1].link;
  EXPECT_EQ(bound.pair(tipA, tipB, armOnly), 0.0);
  EXPECT_GT(bound.link(tipA, armOnly), 0.0);
}

TEST(MotionBound, StillIsZeroAndArgumentsChecked) {
  const MotionBound bound(kr5());
  const Eigen::VectorXd still = Eigen::VectorXd::Zero(kr5().numDofs());
  const int palm = kr5().palmLink(), base = kr5().linkIndex("base_link");
  EXPECT_EQ(bound.link(palm, still), 0.0);
  EXPECT_EQ(bound.pair(base, palm, still), 0.0);
  // The first joint moves the palm, never the base.
  const Eigen::VectorXd turn = 0.1 * Eigen::VectorXd::Unit(kr5().numDofs(), 0);
  EXPECT_GT(bound.link(palm, turn), 0.0);
  EXPECT_EQ(bound.link(base, turn), 0.0);
  EXPECT_EQ(bound.pair(base, palm, turn), bound.link(palm, turn));
  EXPECT_THROW(bound.link(palm, Eigen::VectorXd::Zero(3)), std::invalid_argument);
  EXPECT_THROW(bound.link(-1, turn), std::invalid_argument);
  EXPECT_THROW(bound.pair(base, static_cast<int>(kr5().links().size()), turn),
               std::invalid_argument);
}

/// The KR5 turning 2.4 rad about its base, in a scene of its own with a
/// small thin plate across the palm's path at fraction `where`.
struct PlateCase {
  Scene scene;
  Eigen::VectorXd a, b;
};

PlateCase plateAcrossThePath(double where, double thickness) {
  PlateCase c;
  c.a = kr5().home();
  c.a(1) -= 0.3;  // the arm reaching forward
  c.b = c.a;
  c.b(0) += 2.4;
  const int palm = kr5().palmLink();
  auto palmAt = [&](double t) {
    return forwardKinematics(kr5(), c.a + t * (c.b - c.a))[static_cast<std::size_t>(palm)]
        .translation();
  };
  const Eigen::Vector3d centre = palmAt(where);
  const Eigen::Vector3d along = (palmAt(where + 0.01) - palmAt(where - 0.01)).normalized();
  Obstacle plate;
  plate.name = "plate";
  plate.type = Obstacle::Type::kBox;
  plate.size = Eigen::Vector3d(0.06, 0.06, thickness);  // thin along its z
  plate.pose.linear() =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), along).toRotationMatrix();
  plate.pose.translation() = centre;
  c.scene.name = "plate";
  c.scene.obstacles.push_back(plate);
  return c;
}

TEST(SegmentCertificate, RefusesAThinPlateBetweenTwoSamples) {
  // A 2 mm plate across the palm's path, half way between the states a
  // sampled check at a quarter of the segment looks at (the palm moves
  // about 20 cm between them): the samples miss it, the certificate does not.
  bool missedBySamples = false;
  for (const double where : {0.125, 0.375, 0.625, 0.875}) {
    SCOPED_TRACE(where);
    const PlateCase c = plateAcrossThePath(where, 0.002);
    CollisionChecker checker(test::collisionOf(kr5()), c.scene, nullptr);
    CollisionPair pair;
    ASSERT_FALSE(checker.inCollision(c.a, &pair)) << pair.first << " / " << pair.second;
    ASSERT_FALSE(checker.inCollision(c.b, &pair)) << pair.first << " / " << pair.second;
    // Dense truth: the plate is hit somewhere.
    bool hit = false;
    for (int i = 1; i < 2000 && !hit; ++i)
      hit = checker.inCollision(c.a + (c.b - c.a) * (i / 2000.0));
    ASSERT_TRUE(hit);
    const double length = checker.metric().distance(c.a, c.b);
    const bool sampledValid = checker.isMotionValid(c.a, c.b, length / 4);
    const MotionCertificate certificate = certifySegment(checker, MotionBound(kr5()), c.a, c.b);
    EXPECT_FALSE(certificate.free);
    EXPECT_FALSE(certificate.exhausted);
    EXPECT_GT(certificate.blocked_at, 0.0);
    EXPECT_LT(certificate.blocked_at, where);
    if (sampledValid) missedBySamples = true;
  }
  EXPECT_TRUE(missedBySamples) << "no plate position fell between the samples";
}

/// The plate of plateAcrossThePath(0.5) raised above the palm's path until
/// the path passes it at 1.2-5 cm (`nearest`: how close, densely swept).
PlateCase plateAboveThePath(double* nearest) {
  PlateCase c = plateAcrossThePath(0.5, 0.002);
  auto nearestAlongThePath = [&](const Scene& scene) {
    CollisionChecker checker(test::collisionOf(kr5()), scene, nullptr);
    double d = 1e9;
    for (int i = 0; i <= 400; ++i)
      d = std::min(d, distanceToEverything(checker, c.a + (c.b - c.a) * (i / 400.0)));
    return d;
  };
  *nearest = 0.0;
  for (int raise = 0; raise < 100 && *nearest < 0.012; ++raise) {
    c.scene.obstacles[0].pose.translation().z() += 0.005;
    *nearest = nearestAlongThePath(c.scene);
  }
  return c;
}

TEST(SegmentCertificate, KeepsTheClearanceAsked) {
  // Free at clearance 0 and 1 cm, refused at 5 cm.
  double nearest = 0.0;
  const PlateCase c = plateAboveThePath(&nearest);
  ASSERT_GT(nearest, 0.012);
  ASSERT_LT(nearest, 0.05);
  CollisionChecker checker(test::collisionOf(kr5()), c.scene, nullptr);
  const MotionBound bound(kr5());
  for (const double clearance : {0.0, 0.01}) {
    CertifyOptions options;
    options.clearance = clearance;
    const MotionCertificate certificate = certifySegment(checker, bound, c.a, c.b, options);
    EXPECT_TRUE(certificate.free) << clearance;
    EXPECT_GE(certificate.clearance, clearance);
  }
  CertifyOptions far;
  far.clearance = 0.05;
  EXPECT_FALSE(certifySegment(checker, bound, c.a, c.b, far).free);
}

TEST(SegmentCertificate, AgreesWithADenseSweepInEveryBundledScene) {
  // Random short segments from free states near the obstacles: a segment
  // certified free is free at every state of a dense sweep (FCL), by the
  // clearance asked; one the sweep finds closer is never certified; the
  // reported clearance is FCL's distance at the reported state.
  const MotionBound bound(kr5());
  const auto& objects = test::bundledObjects();
  const db::ObjectDatabase& object = objects.begin()->second;
  int free = 0, refused = 0;
  for (const char* name : {"table", "shelf", "bin"}) {
    SCOPED_TRACE(name);
    Scene scene = loadScene(test::sourcePath(std::string("objects/scenes/") + name + ".json"));
    scene.target_object = objects.begin()->first;
    scene.target_pose = targetPose(scene, object.geometry.mesh_vertices);
    CollisionChecker checker(test::collisionOf(kr5()), scene, &object.geometry);
    std::mt19937_64 rng(11);
    int segments = 0;
    for (int attempt = 0; attempt < 4000 && segments < 16; ++attempt) {
      const Eigen::VectorXd a = randomConfiguration(kr5(), rng);
      const double start = distanceToEverything(checker, a);
      if (start <= 0.0 || start > 0.08) continue;  // free, near something
      Eigen::VectorXd b = a;
      for (Eigen::Index d = 0; d < b.size(); ++d)
        b(d) = std::clamp(a(d) + std::normal_distribution<double>(0.0, 0.15)(rng),
                          kr5().lowerLimits()(d), kr5().upperLimits()(d));
      ++segments;
      CertifyOptions options;
      options.clearance = segments % 2 == 0 ? 0.0 : 0.005;
      const MotionCertificate certificate = certifySegment(checker, bound, a, b, options);
      const Eigen::VectorXd at = a + certificate.at * (b - a);
      // FCL's distance there, between the link and the environment or the
      // two links reported.
      std::vector<double> distance;
      if (certificate.nearest_other_link < 0)
        checker.linkClearances(at, {certificate.nearest_link}, distance,
                               certificate.nearest_target ? CollisionRequest::targetOnly()
                                                          : CollisionRequest::obstaclesOnly());
      else
        checker.pairClearances(at, {{certificate.nearest_link, certificate.nearest_other_link}},
                               distance);
      ASSERT_EQ(distance.size(), 1u);
      EXPECT_NEAR(certificate.clearance, distance[0], 1e-6);
      // Not below the smallest distance there, as the broadphase queries
      // find it: FCL's solver answers the same pair through another path
      // within its tolerance (5e-6 seen), 1e-5 in certifySegment.
      EXPECT_GE(certificate.clearance, distanceToEverything(checker, at) - 1e-5);
      double swept = 1e9;
      for (int i = 0; i <= 200; ++i)
        swept = std::min(swept, distanceToEverything(checker, a + (b - a) * (i / 200.0)));
      if (certificate.free) {
        ++free;
        EXPECT_GE(swept, options.clearance) << "certified, but the sweep comes closer";
      } else {
        ++refused;
      }
      if (swept < options.clearance) {
        EXPECT_FALSE(certificate.free);
      }
    }
    EXPECT_EQ(segments, 16);
  }
  // Both answers occur, so the comparison says something.
  EXPECT_GE(free, 8);
  EXPECT_GE(refused, 8);
}

TEST(SegmentCertificate, ChecksItsArguments) {
  Scene empty;
  CollisionChecker checker(test::collisionOf(kr5()), empty, nullptr);
  const MotionBound bound(kr5());
  const Eigen::VectorXd q = kr5().home();
  CertifyOptions negative;
  negative.clearance = -0.01;
  try {
    certifySegment(checker, bound, q, q, negative);
    FAIL() << "a negative clearance was accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.field(), "clearance");
  }
  EXPECT_THROW(certifySegment(checker, bound, q, Eigen::VectorXd::Zero(2)), InvalidArgument);
  // A segment of no length is its one state: distances from every link
  // with shapes to the obstacles and to the target, one between the links.
  const MotionCertificate still = certifySegment(checker, bound, q, q);
  EXPECT_TRUE(still.free);
  std::vector<int> shaped;
  for (std::size_t l = 0; l < kr5().links().size(); ++l)
    if (!kr5().links()[l].shapes.empty()) shaped.push_back(static_cast<int>(l));
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < shaped.size(); ++i)
    for (std::size_t k = i + 1; k < shaped.size(); ++k)
      pairs += kr5().isCollisionDisabled(shaped[i], shaped[k]) ? 0 : 1;
  // (The obstacles and the target are two distances of each link.)
  EXPECT_EQ(still.queries, 2 * shaped.size() + pairs);
  EXPECT_EQ(still.self_queries, pairs);
  EXPECT_GT(pairs, 0u);
  // A path of one waypoint is that state; none is refused.
  EXPECT_EQ(certifyPath(checker, bound, {q}).queries, still.queries);
  try {
    certifyPath(checker, bound, {});
    FAIL() << "a path without waypoints was accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.field(), "path");
  }
  EXPECT_THROW(certifyPath(checker, bound, {q, Eigen::VectorXd::Zero(2)}), InvalidArgument);
}

TEST(PathCertificate, CarriesItsProofsFromChordToChord) {
  // The plate segment cut into 100 chords (a trajectory's samples): the
  // same verdict as the segment, each distance proof running on across the
  // chords, so the chords cost about what the segment does, not 100 first
  // states.
  double nearest = 0.0;
  const PlateCase c = plateAboveThePath(&nearest);
  CollisionChecker checker(test::collisionOf(kr5()), c.scene, nullptr);
  const MotionBound bound(kr5());
  std::vector<Eigen::VectorXd> chords;
  for (int i = 0; i <= 100; ++i) chords.push_back(c.a + (c.b - c.a) * (i / 100.0));
  for (const double clearance : {0.0, 0.01, 0.05}) {
    SCOPED_TRACE(clearance);
    CertifyOptions options;
    options.clearance = clearance;
    const MotionCertificate segment = certifySegment(checker, bound, c.a, c.b, options);
    const MotionCertificate path = certifyPath(checker, bound, chords, options);
    EXPECT_EQ(path.free, segment.free);
    EXPECT_EQ(path.free, clearance < nearest);
    if (path.free) {
      EXPECT_LE(path.queries, 2 * segment.queries);
      EXPECT_NEAR(path.clearance, segment.clearance, 0.005);
    } else {
      // Blocked where the segment was (positions: the chord's index).
      EXPECT_NEAR(path.blocked_at / 100.0, segment.blocked_at, 0.02);
    }
  }
  const MotionCertificate first = certifySegment(checker, bound, chords[0], chords[1]);
  EXPECT_GT(100 * first.queries, 20 * certifyPath(checker, bound, chords).queries);
}

TEST(PathCertificate, TheHandMayArriveWithinTheClearanceOnlyAtTheEnd) {
  // The plate across the palm's path just beyond the end: the hand stops
  // 2-4 mm short of it. Under the approach rule the hand keeps the 1 cm
  // clearance except over its last 5 cm of travel, where what it keeps
  // shrinks to 0, so the motion is proven; as a transit it is refused, and
  // so is leaving the plate (the same motion backwards: the hand starts
  // within the clearance).
  // Bisection on how far beyond the end the plate stands (0: the palm's
  // centre is in it at the end).
  double lo = 0.0, hi = 0.5, gap = 0.0;
  PlateCase c;
  for (int i = 0; i < 40 && !(gap > 0.002 && gap < 0.004); ++i) {
    const double beyond = (lo + hi) / 2;
    c = plateAcrossThePath(1.0 + beyond, 0.002);
    CollisionChecker checker(test::collisionOf(kr5()), c.scene, nullptr);
    gap = checker.clearance(c.b);
    (gap < 0.003 ? lo : hi) = beyond;
  }
  ASSERT_GT(gap, 0.002);
  ASSERT_LT(gap, 0.004);
  CollisionChecker checker(test::collisionOf(kr5()), c.scene, nullptr);
  const MotionBound bound(kr5());
  CertifyOptions options;
  options.clearance = 0.01;
  options.rule = CertifyRule::kApproach;
  const MotionCertificate arriving = certifySegment(checker, bound, c.a, c.b, options);
  EXPECT_TRUE(arriving.free);
  // It came within the clearance (the rule was used), not nearer than the
  // gap at the end (the smallest distance measured bounds the true one
  // from above).
  EXPECT_LT(arriving.clearance, 0.01);
  EXPECT_GE(arriving.clearance, gap - 1e-5);
  EXPECT_TRUE(kr5().isHandLink(arriving.nearest_link)) << kr5().links()[arriving.nearest_link].name;
  EXPECT_FALSE(certifySegment(checker, bound, c.b, c.a, options).free);
  options.rule = CertifyRule::kTransit;
  const MotionCertificate transit = certifySegment(checker, bound, c.a, c.b, options);
  EXPECT_FALSE(transit.free);
  EXPECT_GT(transit.blocked_at, 0.9);
  // At clearance 0 the rules agree: free.
  options.clearance = 0.0;
  EXPECT_TRUE(certifySegment(checker, bound, c.a, c.b, options).free);
}

}  // namespace
}  // namespace hfts::robot
