// A collision scene that keeps a clearance (CollisionScene, docs/collision.md
// "Clearance"): its checks agree with FCL's distances under the clearance
// rule, measured independently (clearance_rule.h).
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "bundled_objects.h"
#include "clearance_rule.h"
#include "core/invalid_argument.h"
#include "robot/collision_checker.h"
#include "robot_fixture.h"

namespace hfts::robot {
namespace {

const RobotModel& m() {
  return test::kr5Sdh();
}

/// A bundled scene with a bundled object at its target pose.
Scene sceneWith(const std::string& name, const db::ObjectDatabase& object) {
  Scene scene = loadScene(test::sourcePath("objects/scenes/" + name + ".json"));
  scene.target_object = object.name;
  scene.target_pose = targetPose(scene, object.geometry.mesh_vertices);
  return scene;
}

/// Random configurations within the joint limits, half of them near the
/// scene's start (where the arm is near the table and the object is near).
std::vector<Eigen::VectorXd> configurations(const Scene& scene, std::size_t count,
                                            std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0), near(-0.6, 0.6);
  const Eigen::VectorXd start = scene.startFor(m().name()).value_or(m().home());
  std::vector<Eigen::VectorXd> out;
  for (std::size_t i = 0; i < count; ++i) {
    Eigen::VectorXd q(m().numDofs());
    for (int d = 0; d < q.size(); ++d) {
      const double lo = m().lowerLimits()(d), hi = m().upperLimits()(d);
      q(d) = i % 2 == 0 ? lo + unit(rng) * (hi - lo) : std::clamp(start(d) + near(rng), lo, hi);
    }
    out.push_back(std::move(q));
  }
  return out;
}

/// Configurations near contacts: on segments from a free configuration to
/// a colliding one, free states short of the first contact by 1-30 mm of
/// joint travel.
std::vector<Eigen::VectorXd> nearContacts(CollisionChecker& exact,
                                          const std::vector<Eigen::VectorXd>& qs) {
  std::vector<Eigen::VectorXd> out;
  for (std::size_t i = 0; i + 1 < qs.size(); i += 2) {
    const Eigen::VectorXd& a = qs[i];
    const Eigen::VectorXd& b = qs[i + 1];
    if (exact.inCollision(a) || !exact.inCollision(b)) continue;
    double free = 0.0, hit = 1.0;
    for (int k = 0; k < 20; ++k) {
      const double mid = (free + hit) / 2;
      (exact.inCollision(a + (b - a) * mid) ? hit : free) = mid;
    }
    const double length = (b - a).norm();
    for (const double back : {0.001, 0.004, 0.01, 0.03})
      out.push_back(a + (b - a) * std::max(0.0, free - back / length));
  }
  return out;
}

TEST(Clearance, AScenesChecksKeepTheClearanceByFclsDistancesUnderTheRule) {
  // In every bundled scene, at 2 and 20 mm, on random configurations and
  // configurations near contacts: a configuration counts as a contact exactly when it collides or
  // the independent FCL distances of the rule come nearer than the clearance (away from the
  // boundary by 1e-6, FCL's tolerance). Both answers occur.
  const test::ClearanceRule rule(m());
  const db::ObjectDatabase& mug = test::bundledObjects().at("mug");
  for (const char* name : {"table", "shelf", "bin"}) {
    const Scene scene = sceneWith(name, mug);
    for (const double clearance : {0.002, 0.02}) {
      SCOPED_TRACE(std::string(name) + " at " + std::to_string(clearance));
      auto keeping = std::make_shared<const CollisionScene>(
          test::collisionOf(m()), scene, &mug.geometry, nullptr, nullptr, clearance);
      CollisionChecker checker(keeping), exact(test::collisionOf(m()), scene, &mug.geometry);
      EXPECT_EQ(checker.scene().clearance(), clearance);
      int near = 0, kept = 0;
      std::vector<Eigen::VectorXd> qs = configurations(scene, 100, 7);
      for (Eigen::VectorXd& q : nearContacts(exact, configurations(scene, 400, 8)))
        qs.push_back(std::move(q));
      for (const Eigen::VectorXd& q : qs) {
        for (const bool grasp : {false, true}) {
          const CollisionRequest request = grasp ? CollisionRequest::grasp() : CollisionRequest{};
          const bool collides = exact.inCollision(q, request);
          const test::RuleDistance d = rule.at(exact, q, grasp, false, clearance + 0.01);
          if (!collides && std::abs(d.distance - clearance) < 1e-6) continue;
          const bool expected = collides || d.distance < clearance;
          CollisionPair pair;
          ASSERT_EQ(checker.inCollision(q, request, &pair), expected)
              << (grasp ? "grasp rule" : "strict") << ": rule distance " << d.distance << " ("
              << d.what << "), checker names " << pair.first << " / " << pair.second;
          // Asked not to keep it, the scene's checks are the exact ones.
          CollisionRequest strict = request;
          strict.clearance = false;
          ASSERT_EQ(checker.inCollision(q, strict), collides);
          if (!collides) (expected ? near : kept) += 1;
        }
      }
      EXPECT_GE(near, 3);
      EXPECT_GE(kept, 10);
    }
  }
}

TEST(Clearance, AStreamOfStatesGetsTheAnswersOfOneByOne) {
  // validSegments tests states a batch at a time through the grown tier.
  const db::ObjectDatabase& mug = test::bundledObjects().at("mug");
  const Scene scene = sceneWith("shelf", mug);
  auto keeping = std::make_shared<const CollisionScene>(test::collisionOf(m()), scene,
                                                        &mug.geometry, nullptr, nullptr, 0.01);
  CollisionChecker stream(keeping), oneByOne(keeping);
  const std::vector<Eigen::VectorXd> qs = configurations(scene, 200, 11);
  int valid = 0;
  for (std::size_t i = 0; i + 1 < qs.size(); ++i) {
    const std::vector<Eigen::VectorXd> line = {qs[i], qs[i + 1]};
    const bool segment = stream.validSegments(line, 0.05) == 1;
    bool expected = true;
    const int steps =
        static_cast<int>(std::ceil(oneByOne.metric().distance(qs[i], qs[i + 1]) / 0.05));
    for (int k = 1; k <= std::max(1, steps) && expected; ++k)
      expected =
          !oneByOne.inCollision(qs[i] + (qs[i + 1] - qs[i]) * (double(k) / std::max(1, steps)));
    EXPECT_EQ(segment, expected) << i;
    valid += segment ? 1 : 0;
  }
  EXPECT_GT(valid, 0);
}

TEST(Clearance, TheBaseAndTheWristNeedOnlyBeFree) {
  // The KR5's base stands 1 mm above the table: a link that never moves is
  // held to no clearance, so the start keeps 5 mm of it where the moving
  // links do.
  const db::ObjectDatabase& mug = test::bundledObjects().at("mug");
  const Scene scene = sceneWith("table", mug);
  const Eigen::VectorXd start = scene.startFor(m().name()).value_or(m().home());
  CollisionChecker exact(test::collisionOf(m()), scene, &mug.geometry);
  EXPECT_LT(exact.clearance(start), 0.005);  // the base, 1 mm from the table
  const test::RuleDistance moving = test::ClearanceRule(m()).at(exact, start);
  ASSERT_GT(moving.distance, 0.005);
  CollisionChecker keeping(std::make_shared<const CollisionScene>(
      test::collisionOf(m()), scene, &mug.geometry, nullptr, nullptr, 0.005));
  EXPECT_FALSE(keeping.inCollision(start));
  CollisionChecker tooMuch(std::make_shared<const CollisionScene>(
      test::collisionOf(m()), scene, &mug.geometry, nullptr, nullptr, moving.distance + 0.001));
  EXPECT_TRUE(tooMuch.inCollision(start));
  // Nor are link_4 and link_6, two joints apart: 15 mm apart at the start,
  // and the start keeps 2 cm.
  std::vector<double> wrist;
  exact.pairClearances(start, {{m().linkIndex("link_4"), m().linkIndex("link_6")}}, wrist);
  EXPECT_NEAR(wrist[0], 0.015, 0.001);
  ASSERT_GT(moving.distance, 0.02);
  CollisionChecker twoCentimetres(std::make_shared<const CollisionScene>(
      test::collisionOf(m()), scene, &mug.geometry, nullptr, nullptr, 0.02));
  EXPECT_FALSE(twoCentimetres.inCollision(start));
}

TEST(Clearance, ANegativeOrInfiniteClearanceIsRefusedByName) {
  const db::ObjectDatabase& mug = test::bundledObjects().at("mug");
  const Scene scene = sceneWith("table", mug);
  for (const double bad : {-0.001, std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN()}) {
    try {
      CollisionScene s(test::collisionOf(m()), scene, &mug.geometry, nullptr, nullptr, bad);
      ADD_FAILURE() << bad;
    } catch (const InvalidArgument& e) {
      EXPECT_EQ(e.field(), "clearance");
    }
  }
}

}  // namespace
}  // namespace hfts::robot
