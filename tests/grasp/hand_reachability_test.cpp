#include "grasp/hand_reachability.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include "hand_fixture.h"
#include "robot/kinematics.h"
#include "test_meshes.h"

namespace hfts::grasp {
namespace {

const std::filesystem::path kRobotDir = std::filesystem::path(HFTS_SOURCE_DIR) / "robots/kr5_sdh";

const robot::RobotModel& kr5() {
  static const robot::RobotModel model = robot::RobotModel::load(kRobotDir / "kr5_sdh.json");
  return model;
}

/// The default map, built once for the suite.
const db::HandMap& defaultMap() {
  static const db::HandMap map = buildHandMap(kr5());
  return map;
}

const HandReachability& fast() {
  static const HandReachability r(kr5(), defaultMap());
  return r;
}

const HandReachability& thorough() {
  static const HandReachability r(kr5(), defaultMap(), HandQueryOptions::thorough());
  return r;
}

/// The KR5 with its config edited, e.g. another fingertip.
robot::RobotModel editedKr5(const std::function<void(nlohmann::json&)>& edit) {
  nlohmann::json config = nlohmann::json::parse(test::readBytes(kRobotDir / "kr5_sdh.json"));
  edit(config);
  return robot::RobotModel::fromStrings(test::readBytes(kRobotDir / "kr5_sdh.urdf"), config.dump(),
                                        "edited kr5_sdh");
}

using Posture = test::HandPosture;

Posture postureOf(const Eigen::VectorXd& hand) {
  return test::handPostureOf(kr5(), hand);
}

Posture randomGraspPosture(std::mt19937_64& rng) {
  return test::randomGraspPosture(kr5(), rng);
}

using test::randomPose;

struct Triple {
  Eigen::Matrix3Xd contacts = Eigen::Matrix3Xd(3, 3);
  Eigen::Matrix3Xd outward = Eigen::Matrix3Xd(3, 3);
};

/// A triple the hand reaches exactly: fingertips moved by a rigid motion,
/// outward normals opposite to the pads, contacts in shuffled order.
Triple reachableTriple(const Eigen::Matrix3d& tips, const Eigen::Matrix3d& pads,
                       const Eigen::Isometry3d& pose, std::mt19937_64& rng) {
  std::array<int, 3> order = {0, 1, 2};
  std::shuffle(order.begin(), order.end(), rng);
  Triple t;
  for (int c = 0; c < 3; ++c) {
    t.contacts.col(c) = pose * Eigen::Vector3d(tips.col(order[c]));
    t.outward.col(c) = -(pose.linear() * pads.col(order[c]));
  }
  return t;
}

/// Contacts on an equilateral triangle of edge `edge` whose outward normals
/// are tilted by `tilt` (rad) from pointing away from the centroid.
Triple triangle(double edge, double tilt) {
  Triple t;
  for (int c = 0; c < 3; ++c) {
    const double a = 2 * M_PI * c / 3;
    const Eigen::Vector3d radial(std::cos(a), std::sin(a), 0);
    t.contacts.col(c) = edge / std::sqrt(3.0) * radial;
    t.outward.col(c) = std::cos(tilt) * radial + std::sin(tilt) * Eigen::Vector3d::UnitZ();
  }
  return t;
}

/// R recomputed from the answer by the robot's forward kinematics: the
/// answer's posture and pose achieve the reported residual.
double residualOf(const HandQuery& answer, const Triple& t) {
  const Posture p = postureOf(answer.hand_configuration);
  const double lambda = defaultMap().parameters.normal_weight;
  double sum = 0;
  for (int c = 0; c < 3; ++c) {
    const int f = answer.finger_of_contact[static_cast<std::size_t>(c)];
    const Eigen::Vector3d tip = answer.palm_pose * Eigen::Vector3d(p.tips.col(f));
    const Eigen::Vector3d pad = answer.palm_pose.linear() * p.pads.col(f);
    sum += (tip - t.contacts.col(c)).squaredNorm() +
           lambda * lambda * (pad + t.outward.col(c)).squaredNorm();
  }
  return std::sqrt(sum / 3);
}

void expectConsistent(const HandQuery& answer, const Triple& t) {
  ASSERT_EQ(answer.finger_of_contact.size(), 3u);
  std::vector<int> fingers = answer.finger_of_contact;
  std::sort(fingers.begin(), fingers.end());
  EXPECT_EQ(fingers, (std::vector<int>{0, 1, 2}));
  Eigen::VectorXd q = kr5().home();
  q.tail(kr5().numHandDofs()) = answer.hand_configuration;
  EXPECT_TRUE(kr5().withinLimits(q));
  EXPECT_NEAR(residualOf(answer, t), answer.residual, 1e-9);
  const Posture p = postureOf(answer.hand_configuration);
  EXPECT_TRUE(isGraspPosture(p.tips, p.pads, defaultMap().parameters));
}

/// Where the answer's fingertips land, by forward kinematics.
void expectFingertipsOnContacts(const HandQuery& answer, const Triple& t, double tolerance) {
  const Posture p = postureOf(answer.hand_configuration);
  for (int c = 0; c < 3; ++c) {
    const int f = answer.finger_of_contact[static_cast<std::size_t>(c)];
    const Eigen::Vector3d tip = answer.palm_pose * Eigen::Vector3d(p.tips.col(f));
    const Eigen::Vector3d pad = answer.palm_pose.linear() * p.pads.col(f);
    EXPECT_LT((tip - t.contacts.col(c)).norm(), tolerance) << "contact " << c;
    EXPECT_GT(pad.dot(-t.outward.col(c)), std::cos(0.05)) << "contact " << c;
  }
}

TEST(HandMapBuilder, KeepsGraspPosturesOnlyAndIsDeterministic) {
  HandMapOptions options;
  options.num_samples = 300;
  const db::HandMap a = buildHandMap(kr5(), options);
  const db::HandMap b = buildHandMap(kr5(), options);
  ASSERT_EQ(a.numSamples(), 300u);
  EXPECT_EQ(a.configurations, b.configurations);
  EXPECT_EQ(a.descriptors, b.descriptors);
  EXPECT_GT(a.num_draws, 300u);
  EXPECT_EQ(a.dof_names,
            std::vector<std::string>(kr5().dofNames().begin() + 6, kr5().dofNames().end()));
  EXPECT_EQ(a.finger_names, (std::vector<std::string>{"finger_1", "finger_2", "thumb"}));
  for (Eigen::Index s = 0; s < a.configurations.rows(); ++s) {
    const Posture p = postureOf(a.configurations.row(s).transpose());
    const Eigen::Matrix3d tips = Eigen::Map<const Eigen::Matrix3d>(a.positions.row(s).data());
    const Eigen::Matrix3d pads = Eigen::Map<const Eigen::Matrix3d>(a.normals.row(s).data());
    ASSERT_LT((tips - p.tips).norm(), 1e-12) << s;
    ASSERT_LT((pads - p.pads).norm(), 1e-12) << s;
    ASSERT_TRUE(isGraspPosture(tips, pads, options)) << s;
  }
  options.seed = 2;
  EXPECT_NE(buildHandMap(kr5(), options).configurations, a.configurations);
}

TEST(HandMapBuilder, DefaultMapIsSmall) {
  EXPECT_EQ(defaultMap().numSamples(), 8192u);
  const auto doubles = defaultMap().configurations.size() + defaultMap().positions.size() +
                       defaultMap().normals.size() + defaultMap().descriptors.size();
  EXPECT_LT(static_cast<double>(doubles) * 8, 3e6);  // bytes
}

TEST(HandMapBuilder, RejectsBadOptionsAndHandsOfOneFingertip) {
  for (const auto& edit : std::vector<std::function<void(HandMapOptions&)>>{
           [](HandMapOptions& o) { o.num_samples = 0; },
           [](HandMapOptions& o) { o.max_draws = o.num_samples - 1; },
           [](HandMapOptions& o) { o.normal_weight = 0; },
           [](HandMapOptions& o) { o.min_fingertip_distance = NAN; },
           [](HandMapOptions& o) { o.friction = -1; }}) {
    HandMapOptions options;
    edit(options);
    EXPECT_THROW(buildHandMap(kr5(), options), std::invalid_argument);
  }
  const robot::RobotModel oneFinger = editedKr5([](nlohmann::json& c) {
    c["fingertips"].erase(2);
    c["fingertips"].erase(1);
  });
  test::expectErrorMentioning<robot::ModelError>([&] { buildHandMap(oneFinger); },
                                                 {"1 fingertips", "2 to 4"});
}

TEST(IsGraspPosture, OpposingPadsQualifyOthersDoNot) {
  const HandMapOptions options;
  Eigen::Matrix3d tips, pads;
  // Two fingers against a thumb, 6 cm apart, pads facing each other.
  tips << 0.03, 0.03, -0.03, 0.03, -0.03, 0, 0, 0, 0;
  pads << -1, -1, 1, 0, 0, 0, 0, 0, 0;
  EXPECT_TRUE(isGraspPosture(tips, pads, options));
  EXPECT_FALSE(isGraspPosture(tips, -pads, options));  // pads face away
  Eigen::Matrix3d parallel = pads;
  parallel.row(0).setZero();
  parallel.row(2).setConstant(-1);  // all pads push the same way
  EXPECT_FALSE(isGraspPosture(tips, parallel, options));
  Eigen::Matrix3d close = tips;
  close.col(2) = close.col(0) + Eigen::Vector3d(0.005, 0, 0);
  EXPECT_FALSE(isGraspPosture(close, pads, options));
  // A tilt within the friction cone (atan 0.5 = 26.6 deg) still squeezes.
  Eigen::Matrix3d tilted = pads;
  tilted.col(2) = Eigen::Vector3d(std::cos(0.4), 0, std::sin(0.4));
  EXPECT_TRUE(isGraspPosture(tips, tilted, options));
  tilted.col(2) = Eigen::Vector3d(std::cos(1.0), 0, std::sin(1.0));
  EXPECT_FALSE(isGraspPosture(tips, tilted, options));
}

TEST(HandDescriptor, InvariantUnderRigidMotionNotUnderMirroring) {
  std::mt19937_64 rng(1);
  const Posture p = randomGraspPosture(rng);
  const Eigen::Isometry3d pose = randomPose(rng);
  const auto d = handDescriptor(p.tips, p.pads, 0.03);
  EXPECT_LT((handDescriptor(pose * p.tips, pose.linear() * p.pads, 0.03) - d).norm(), 1e-12);
  const Eigen::Matrix3d mirror = Eigen::Vector3d(1, 1, -1).asDiagonal();
  const auto m = handDescriptor(mirror * p.tips, mirror * p.pads, 0.03);
  EXPECT_LT((m.head<3>() - d.head<3>()).norm(), 1e-12);  // same triangle
  EXPECT_GT((m - d).norm(), 1e-3);                       // other chirality
}

TEST(HandReachability, ExactForMapSamples) {
  std::mt19937_64 rng(5);
  for (int i = 0; i < 100; ++i) {
    const auto s = static_cast<Eigen::Index>(rng() % defaultMap().numSamples());
    const Eigen::Matrix3d tips =
        Eigen::Map<const Eigen::Matrix3d>(defaultMap().positions.row(s).data());
    const Eigen::Matrix3d pads =
        Eigen::Map<const Eigen::Matrix3d>(defaultMap().normals.row(s).data());
    const Triple t = reachableTriple(tips, pads, randomPose(rng), rng);
    const HandQuery answer = fast().query(t.contacts, t.outward);
    SCOPED_TRACE(i);
    EXPECT_LT(answer.residual, 1e-6);
    expectConsistent(answer, t);
    expectFingertipsOnContacts(answer, t, 1e-6);
  }
}

// Random grasp postures lie between map samples: the refinement must find
// them. The thorough search reaches nearly all, the default most.
TEST(HandReachability, ZeroForTheFingertipsOfRandomGraspPostures) {
  std::mt19937_64 rng(7);
  int thoroughReached = 0, fastReached = 0;
  const int count = 200;
  for (int i = 0; i < count; ++i) {
    const Posture p = randomGraspPosture(rng);
    const Triple t = reachableTriple(p.tips, p.pads, randomPose(rng), rng);
    SCOPED_TRACE(i);
    const HandQuery answer = thorough().query(t.contacts, t.outward);
    expectConsistent(answer, t);
    EXPECT_LT(answer.residual, 0.01);
    if (answer.residual < 1e-3) {
      ++thoroughReached;
      EXPECT_LT(answer.position_error, 1e-3);
      expectFingertipsOnContacts(answer, t, 1.5e-3);
    }
    const HandQuery quick = fast().query(t.contacts, t.outward);
    expectConsistent(quick, t);
    EXPECT_LT(quick.residual, 0.03);
    fastReached += quick.residual < 1e-3;
  }
  EXPECT_GE(thoroughReached, count * 97 / 100);  // measured: 197 of 200
  EXPECT_GE(fastReached, count * 65 / 100);      // measured: 152 of 200
}

TEST(HandReachability, LargeForImpossibleTriples) {
  const Triple tripod = triangle(0.08, 0.0);
  const double reachable = thorough().query(tripod.contacts, tripod.outward).residual;
  EXPECT_LT(reachable, 1e-6);
  for (const auto& [name, t] : {std::pair<const char*, Triple>{"40 cm apart", triangle(0.4, 0.0)},
                                {"normals parallel", triangle(0.08, M_PI / 2)},
                                {"normals inward", triangle(0.08, M_PI)}}) {
    SCOPED_TRACE(name);
    const HandQuery answer = thorough().query(t.contacts, t.outward);
    EXPECT_GT(answer.residual, 0.02);
    expectConsistent(answer, t);
    EXPECT_GT(fast().query(t.contacts, t.outward).residual, 0.02);
  }
}

TEST(HandReachability, SameResidualForAnyContactOrderAndRigidMotion) {
  std::mt19937_64 rng(9);
  for (int i = 0; i < 20; ++i) {
    Triple t = i % 2 == 0 ? triangle(0.03 + 0.01 * i, 0.1 * i) : Triple{};
    if (i % 2 == 1) {
      const Posture p = randomGraspPosture(rng);
      t = reachableTriple(p.tips, p.pads, randomPose(rng), rng);
    }
    const double r = fast().query(t.contacts, t.outward).residual;
    std::array<int, 3> order = {0, 1, 2};
    while (std::next_permutation(order.begin(), order.end())) {
      Triple permuted;
      for (int c = 0; c < 3; ++c) {
        permuted.contacts.col(c) = t.contacts.col(order[c]);
        permuted.outward.col(c) = t.outward.col(order[c]);
      }
      const HandQuery answer = fast().query(permuted.contacts, permuted.outward);
      EXPECT_NEAR(answer.residual, r, 1e-6 + 1e-6 * r) << i;
    }
    const Eigen::Isometry3d pose = randomPose(rng);
    const Eigen::Matrix3Xd moved = pose * t.contacts;
    EXPECT_NEAR(fast().query(moved, pose.linear() * t.outward).residual, r, 1e-6 + 1e-6 * r);
  }
}

TEST(HandReachability, AlternativesAreDistinctPosturesOnTheContactsBestFirst) {
  constexpr double kTolerance = 0.002, kDifferent = 0.05;
  // The symmetric tripod: the hand takes it with several finger assignments.
  const Triple tripod = triangle(0.08, 0.0);
  const std::vector<HandQuery> others =
      thorough().queryAlternatives(tripod.contacts, tripod.outward, kTolerance, kDifferent);
  ASSERT_GE(others.size(), 2u);
  for (std::size_t i = 0; i < others.size(); ++i) {
    SCOPED_TRACE(i);
    expectConsistent(others[i], tripod);
    EXPECT_LE(others[i].position_error, kTolerance);
    expectFingertipsOnContacts(others[i], tripod, 2 * kTolerance);
    if (i > 0) {
      EXPECT_LE(others[i - 1].residual, others[i].residual);
    }
    for (std::size_t j = 0; j < i; ++j)
      EXPECT_TRUE(
          others[i].finger_of_contact != others[j].finger_of_contact ||
          (others[i].hand_configuration - others[j].hand_configuration).cwiseAbs().maxCoeff() >=
              kDifferent)
          << "answers " << j << " and " << i << " are the same posture";
  }
  // Every candidate is finished: the best is at least as good as query()'s.
  std::mt19937_64 rng(3);
  for (int i = 0; i < 20; ++i) {
    const Posture p = randomGraspPosture(rng);
    const Triple t = reachableTriple(p.tips, p.pads, randomPose(rng), rng);
    const HandQuery one = thorough().query(t.contacts, t.outward);
    const std::vector<HandQuery> all = thorough().queryAlternatives(t.contacts, t.outward, 0.01);
    if (one.position_error > 0.01) continue;
    ASSERT_FALSE(all.empty()) << i;
    EXPECT_LE(all.front().residual, one.residual + 1e-12) << i;
  }
  // Nothing reaches contacts 40 cm apart.
  const Triple wide = triangle(0.4, 0.0);
  EXPECT_TRUE(thorough().queryAlternatives(wide.contacts, wide.outward, kTolerance).empty());
  test::expectErrorMentioning<std::invalid_argument>(
      [&] { thorough().queryAlternatives(tripod.contacts, tripod.outward, -1.0); },
      {"maxPositionError"});
}

TEST(HandReachability, SamePostureMeansSameFingersAndCloseJoints) {
  const Triple tripod = triangle(0.08, 0.0);
  const HandQuery a = thorough().query(tripod.contacts, tripod.outward);
  HandQuery b = a;
  EXPECT_TRUE(samePosture(a, b, 0.05));
  b.hand_configuration(0) += 0.04;
  EXPECT_TRUE(samePosture(a, b, 0.05));
  b.hand_configuration(0) += 0.02;
  EXPECT_FALSE(samePosture(a, b, 0.05));
  b = a;
  std::swap(b.finger_of_contact[0], b.finger_of_contact[1]);
  EXPECT_FALSE(samePosture(a, b, 0.05));
}

TEST(HandReachability, RejectsInvalidArgumentsNamingThem) {
  const Triple t = triangle(0.08, 0.0);
  test::expectErrorMentioning<std::invalid_argument>(
      [&] { fast().query(t.contacts.leftCols(2), t.outward); }, {"contactPositions", "3 x 2"});
  Triple bad = t;
  bad.contacts(1, 1) = NAN;
  test::expectErrorMentioning<std::invalid_argument>(
      [&] { fast().query(bad.contacts, bad.outward); }, {"contactPositions", "non-finite"});
  bad = t;
  bad.outward.col(2) *= 2;
  test::expectErrorMentioning<std::invalid_argument>(
      [&] { fast().query(bad.contacts, bad.outward); }, {"outwardContactNormals", "unit"});
  HandQueryOptions options;
  options.neighbours = 0;
  test::expectErrorMentioning<std::invalid_argument>(
      [&] { HandReachability(kr5(), defaultMap(), options); }, {"neighbours"});
  options = {};
  options.search_tolerance = -1;
  EXPECT_THROW(HandReachability(kr5(), defaultMap(), options), std::invalid_argument);
}

TEST(HandReachability, RejectsAMapOfAnotherHand) {
  const auto expectMismatch = [](const robot::RobotModel& robot, db::HandMap map,
                                 const std::string& problem) {
    test::expectErrorMentioning<robot::ModelError>([&] { HandReachability(robot, std::move(map)); },
                                                   {"hand map does not match", problem});
  };
  db::HandMap map = defaultMap();
  map.robot_name = "other";
  expectMismatch(kr5(), map, "built for 'other'");
  map = defaultMap();
  std::swap(map.finger_names[0], map.finger_names[1]);
  expectMismatch(kr5(), map, "fingers differ");
  map = defaultMap();
  map.dof_names[0] = "wrist";
  expectMismatch(kr5(), map, "DoF names differ");
  map = defaultMap();
  map.descriptor = "something-else";
  expectMismatch(kr5(), map, "descriptor");
  const robot::RobotModel longerTips = editedKr5([](nlohmann::json& c) {
    for (auto& tip : c["fingertips"]) tip["point"][2] = 0.05;
  });
  expectMismatch(longerTips, defaultMap(), "forward kinematics does not reproduce");
  const robot::RobotModel twoFingers =
      editedKr5([](nlohmann::json& c) { c["fingertips"].erase(2); });
  EXPECT_THROW(HandReachability(twoFingers, defaultMap()), robot::ModelError);
  map = defaultMap();
  map.normals(3, 0) = 2.0;
  EXPECT_THROW(HandReachability(kr5(), map), db::DatabaseError);
}

}  // namespace
}  // namespace hfts::grasp
