// The sphere tier is conservative in single precision: every pair whose
// geometry touches in double precision is reported, by the
// one-configuration kernel and by the batch kernel alike.
#include "sphere_tier.h"

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <utility>
#include <vector>

#include "robot/kinematics.h"
#include "robot/scene.h"
#include "robot_fixture.h"

namespace hfts::robot {
namespace {

const RobotModel& m() {
  return test::kr5Sdh();
}

/// The scene's primitives as tier items.
std::vector<SphereTier::Item> items(const Scene& scene) {
  std::vector<SphereTier::Item> out;
  for (const Obstacle& o : scene.obstacles)
    out.push_back(
        {static_cast<CollisionShape::Type>(o.type), o.size, o.pose.inverse(), false, std::nullopt});
  return out;
}

using PairKey = std::pair<int, int>;  // (link, item) or (link, 1000 + other link)

PairKey key(const SphereTier::Pair& p) {
  return {p.link, p.other_link < 0 ? static_cast<int>(p.item) : 1000 + p.other_link};
}

/// Points on the surface of every link's shapes (link frame), 300 a shape.
const std::vector<std::vector<Eigen::Vector3d>>& surfaceSamples() {
  static const std::vector<std::vector<Eigen::Vector3d>> samples = [] {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<std::vector<Eigen::Vector3d>> out(m().links().size());
    for (std::size_t l = 0; l < out.size(); ++l)
      for (const CollisionShape& shape : m().links()[l].shapes)
        for (int i = 0; i < 300; ++i) {
          Eigen::Vector3d p(u(rng), u(rng), u(rng));
          if (shape.type == CollisionShape::Type::kBox) {
            p(i % 3) = p(i % 3) < 0 ? -1.0 : 1.0;  // onto a face
            p = p.cwiseProduct(shape.size / 2);
          } else if (shape.type == CollisionShape::Type::kSphere) {
            p = p.normalized() * shape.size.x();
          } else if (i % 4 == 0) {  // cylinder cap
            p.head<2>() *= shape.size.x() / std::max(1.0, p.head<2>().norm());
            p.z() = (p.z() < 0 ? -0.5 : 0.5) * shape.size.y();
          } else {  // cylinder side
            p.head<2>() = p.head<2>().normalized() * shape.size.x();
            p.z() *= shape.size.y() / 2;
          }
          out[l].push_back(shape.origin * p);
        }
    return out;
  }();
  return samples;
}

/// The pairs whose geometry touches (a sampled surface point of one inside
/// the other), in double precision: the tier must report each of them.
std::set<PairKey> touchingGeometry(const Scene& scene, const std::vector<SphereTier::Item>& env,
                                   const Eigen::VectorXd& q) {
  const LinkPoses poses = forwardKinematics(m(), q);
  const std::vector<std::vector<Eigen::Vector3d>>& samples = surfaceSamples();
  std::set<PairKey> out;
  for (std::size_t l = 0; l < samples.size(); ++l) {
    const Eigen::Isometry3d world = scene.robot_base * poses[l];
    for (std::size_t i = 0; i < env.size(); ++i)
      for (const Eigen::Vector3d& p : samples[l])
        if (primitiveSignedDistance(env[i].type, env[i].size, env[i].to_local * (world * p)) <= 0) {
          out.insert({static_cast<int>(l), static_cast<int>(i)});
          break;
        }
    for (std::size_t o = 0; o < samples.size(); ++o) {
      if (o == l || m().isCollisionDisabled(static_cast<int>(l), static_cast<int>(o))) continue;
      const Eigen::Isometry3d toOther = poses[o].inverse() * poses[l];
      for (const Eigen::Vector3d& p : samples[l])
        if (signedDistance(m().links()[o], toOther * p) <= 0) {
          out.insert({static_cast<int>(std::min(l, o)), 1000 + static_cast<int>(std::max(l, o))});
          break;
        }
    }
  }
  return out;
}

/// The pairs the tier reports for q[lane] of a batch.
std::vector<std::set<PairKey>> reported(SphereTier& tier, const std::vector<Eigen::VectorXd>& q) {
  std::vector<const Eigen::VectorXd*> pointers;
  for (const Eigen::VectorXd& c : q) pointers.push_back(&c);
  std::vector<std::set<PairKey>> out(q.size());
  std::vector<float> scratch;
  tier.forEachTouchingPair(pointers.data(), pointers.size(), scratch,
                           [&](const SphereTier::Pair& p, std::uint32_t lanes) -> std::uint32_t {
                             for (std::size_t i = 0; i < q.size(); ++i)
                               if (((lanes >> i) & 1u) != 0) out[i].insert(key(p));
                             return ~0u;  // keep every lane: collect all pairs
                           });
  return out;
}

Eigen::VectorXd randomConfiguration(std::mt19937_64& rng) {
  Eigen::VectorXd q(m().numDofs());
  for (Eigen::Index d = 0; d < q.size(); ++d)
    q(d) = std::uniform_real_distribution<double>(m().lowerLimits()(d), m().upperLimits()(d))(rng);
  return q;
}

TEST(SphereTier, ReportsEveryPairWhoseGeometryTouches) {
  for (const char* name : {"table", "shelf", "bin"}) {
    SCOPED_TRACE(name);
    const Scene scene =
        loadScene(test::sourcePath(std::string("objects/scenes/") + name + ".json"));
    const std::vector<SphereTier::Item> env = items(scene);
    SphereTier tier(test::collisionOf(m()), scene.robot_base, env);
    std::mt19937_64 rng(7);
    std::size_t checked = 0, touching = 0;
    for (int round = 0; round < 20; ++round) {
      std::vector<Eigen::VectorXd> batch;
      for (std::size_t i = 0; i < tier.batchSize(); ++i) batch.push_back(randomConfiguration(rng));
      const std::vector<std::set<PairKey>> lanes = reported(tier, batch);
      for (std::size_t i = 0; i < batch.size(); ++i) {
        const std::set<PairKey> expected = touchingGeometry(scene, env, batch[i]);
        const std::set<PairKey> single = reported(tier, {batch[i]}).front();
        for (const PairKey& pair : expected) {
          EXPECT_TRUE(lanes[i].count(pair))
              << "batch misses link " << pair.first << " / " << pair.second;
          EXPECT_TRUE(single.count(pair))
              << "single misses link " << pair.first << " / " << pair.second;
        }
        touching += expected.size();
        ++checked;
      }
    }
    EXPECT_GT(touching, checked);  // the configurations do touch things
  }
}

TEST(SphereTier, AFreeConfigurationInABatchIsReportedLikeAlone) {
  const Scene scene = loadScene(test::sourcePath("objects/scenes/table.json"));
  SphereTier tier(test::collisionOf(m()), scene.robot_base, items(scene));
  // home is clear of everything; beside colliding configurations in a
  // batch it must still get no pair.
  std::mt19937_64 rng(3);
  std::vector<Eigen::VectorXd> batch(tier.batchSize(), m().home());
  for (std::size_t i = 1; i < batch.size(); i += 2) batch[i] = randomConfiguration(rng);
  const std::vector<std::set<PairKey>> lanes = reported(tier, batch);
  const std::set<PairKey> alone = reported(tier, {m().home()}).front();
  for (std::size_t i = 0; i < batch.size(); i += 2) EXPECT_EQ(lanes[i], alone);
}

}  // namespace
}  // namespace hfts::robot
