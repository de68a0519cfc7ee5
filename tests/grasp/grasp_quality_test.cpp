#include "grasp/grasp_quality.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include <random>

namespace hfts::grasp {
namespace {

/// Contacts on the equator of a unit-radius sphere at the given angles,
/// normals pointing at its centre.
GraspQualityRequest equator(const std::vector<double>& degrees) {
  GraspQualityRequest r;
  r.positions.resize(3, static_cast<Eigen::Index>(degrees.size()));
  r.normals.resize(3, r.positions.cols());
  for (std::size_t i = 0; i < degrees.size(); ++i) {
    const double a = degrees[i] * M_PI / 180.0;
    r.positions.col(static_cast<Eigen::Index>(i)) << std::cos(a), std::sin(a), 0.0;
    r.normals.col(static_cast<Eigen::Index>(i)) = -r.positions.col(static_cast<Eigen::Index>(i));
  }
  return r;
}

/// Contacts on a 5 cm sphere with roughly inward, perturbed normals.
GraspQualityRequest randomGrasp(int contacts, std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  GraspQualityRequest r;
  r.positions.resize(3, contacts);
  r.normals.resize(3, contacts);
  for (int i = 0; i < contacts; ++i) {
    const Eigen::Vector3d p = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    r.positions.col(i) = 0.05 * p;
    r.normals.col(i) = (-p + 0.3 * Eigen::Vector3d(g(rng), g(rng), g(rng))).normalized();
  }
  r.torque_scale = 0.05;
  return r;
}

/// Reference epsilon by brute force: every hyperplane through 6 wrenches
/// that supports the whole set is a facet plane; the origin is strictly
/// inside when it lies strictly inside every one of them.
double bruteForceEpsilon(const Eigen::Matrix<double, 6, Eigen::Dynamic>& w) {
  const int m = static_cast<int>(w.cols());
  const double scale = w.cwiseAbs().maxCoeff();
  double best = std::numeric_limits<double>::infinity();
  bool anyFacet = false;
  std::vector<int> pick = {0, 1, 2, 3, 4, 5};
  while (true) {
    Eigen::MatrixXd edges(5, 6);
    for (int j = 1; j < 6; ++j) edges.row(j - 1) = (w.col(pick[j]) - w.col(pick[0])).transpose();
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(edges, Eigen::ComputeFullV);
    if (svd.singularValues()(4) > 1e-9 * scale) {
      const Eigen::VectorXd a = svd.matrixV().col(5);
      double b = a.dot(w.col(pick[0]));
      const Eigen::VectorXd side = (a.transpose() * w).transpose().array() - b;
      const double tol = 1e-9 * scale;
      const bool below = (side.array() <= tol).all(), above = (side.array() >= -tol).all();
      if (below || above) {
        if (above) b = -b;  // orient the normal outwards
        anyFacet = true;
        best = std::min(best, b);  // |a| = 1: distance of the origin inside
      }
    }
    int i = 5;
    while (i >= 0 && pick[static_cast<std::size_t>(i)] == m - 6 + i) --i;
    if (i < 0) break;
    ++pick[static_cast<std::size_t>(i)];
    for (int j = i + 1; j < 6; ++j)
      pick[static_cast<std::size_t>(j)] = pick[static_cast<std::size_t>(j - 1)] + 1;
  }
  return anyFacet && best > 0 ? best : 0.0;
}

TEST(GraspQuality, ThreeContactsAt120DegreesAreStable) {
  EXPECT_GT(graspQuality(equator({0, 120, 240})).epsilon, 0.0);
}

TEST(GraspQuality, ZeroWhenNormalsAreParallelOrTooFewContacts) {
  GraspQualityRequest parallel = equator({0, 120, 240});
  for (Eigen::Index i = 0; i < 3; ++i) parallel.normals.col(i) = Eigen::Vector3d::UnitX();
  EXPECT_EQ(graspQuality(parallel).epsilon, 0.0);
  // Two opposing contacts cannot resist a torque about their common axis.
  EXPECT_EQ(graspQuality(equator({0, 180})).epsilon, 0.0);
  EXPECT_EQ(graspQuality(equator({0})).epsilon, 0.0);
  // Duplicated contacts add nothing and break nothing.
  EXPECT_EQ(graspQuality(equator({0, 0, 0})).epsilon, 0.0);
  EXPECT_NEAR(graspQuality(equator({0, 120, 240, 240})).epsilon,
              graspQuality(equator({0, 120, 240})).epsilon, 1e-12);
}

TEST(GraspQuality, InvariantUnderPermutationAndRigidMotion) {
  const GraspQualityRequest r = equator({10, 130, 250});
  const double epsilon = graspQuality(r).epsilon;
  GraspQualityRequest permuted = r;
  permuted.positions << r.positions.col(2), r.positions.col(0), r.positions.col(1);
  permuted.normals << r.normals.col(2), r.normals.col(0), r.normals.col(1);
  EXPECT_NEAR(graspQuality(permuted).epsilon, epsilon, 1e-9 * epsilon);
  const Eigen::Isometry3d motion = Eigen::Translation3d(0.3, -1.2, 2.0) *
                                   Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized());
  GraspQualityRequest moved = r;
  moved.positions = motion * r.positions;
  moved.normals = motion.linear() * r.normals;
  moved.center = motion * r.center;
  EXPECT_NEAR(graspQuality(moved).epsilon, epsilon, 1e-9 * epsilon);
}

TEST(GraspQuality, GrowsWithFriction) {
  GraspQualityRequest r = equator({0, 100, 230});
  double previous = 0.0;
  for (const double mu : {0.2, 0.4, 0.6, 0.8}) {
    r.friction = mu;
    const double epsilon = graspQuality(r).epsilon;
    EXPECT_GT(epsilon, previous) << "mu " << mu;
    previous = epsilon;
  }
}

TEST(GraspQuality, OutwardNormalsAreTurnedAround) {
  GraspQualityRequest inward = equator({0, 120, 240});
  GraspQualityRequest outward = inward;
  outward.normals = -inward.normals;
  outward.direction = NormalDirection::kOutward;
  EXPECT_DOUBLE_EQ(graspQuality(outward).epsilon, graspQuality(inward).epsilon);
}

TEST(GraspQuality, MatchesABruteForceReferenceOnRandomGrasps) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.2, 1.0);
  int positive = 0;
  for (int trial = 0; trial < 40; ++trial) {
    GraspQualityRequest r = randomGrasp(3 + trial % 2, rng);
    r.friction = u(rng);
    r.cone_edges = 4;
    const double expected = bruteForceEpsilon(contactWrenches(r));
    const double actual = graspQuality(r).epsilon;
    EXPECT_NEAR(actual, expected, 1e-9 * std::max(expected, 1e-12)) << "trial " << trial;
    positive += expected > 0;
  }
  EXPECT_GT(positive, 10);  // the comparison covers stable grasps, not only zeros
}

// The incremental hull stops once no remaining wrench sees the facet
// nearest the origin; at the force-closure boundary that facet passes
// within a hair of the origin. Friction just below and just above the
// boundary (found by bisection) must give what brute force gives.
TEST(GraspQuality, MatchesABruteForceReferenceAcrossTheForceClosureBoundary) {
  std::mt19937_64 rng(5);
  int positive = 0, zero = 0;
  for (int trial = 0; trial < 20; ++trial) {
    GraspQualityRequest r = randomGrasp(3, rng);
    r.cone_edges = 4;
    double unstable = 0.01, stable = 2.0;
    r.friction = stable;
    if (graspQuality(r).epsilon == 0.0) continue;
    for (int step = 0; step < 30; ++step) {
      r.friction = 0.5 * (unstable + stable);
      (graspQuality(r).epsilon > 0.0 ? stable : unstable) = r.friction;
    }
    for (const double mu : {unstable * (1 - 1e-4), stable * (1 + 1e-4)}) {
      r.friction = mu;
      const double expected = bruteForceEpsilon(contactWrenches(r));
      const double actual = graspQuality(r).epsilon;
      EXPECT_NEAR(actual, expected, 1e-9 * std::max(expected, 1e-12))
          << "trial " << trial << ", mu " << mu;
      positive += expected > 0;
      zero += expected == 0;
    }
  }
  EXPECT_GT(positive, 5);
  EXPECT_GT(zero, 5);
}

/// Expects the incremental hull to give Qhull's epsilon to 1e-9 relative;
/// returns whether the grasp is stable.
bool compareWithQhull(GraspQualityRequest r, int trial) {
  const double fast = graspQuality(r).epsilon;
  r.use_qhull = true;
  const double qhull = graspQuality(r).epsilon;
  EXPECT_NEAR(fast, qhull, 1e-9 * std::max(qhull, 1e-12)) << "trial " << trial;
  return qhull > 0;
}

TEST(GraspQuality, IncrementalHullAgreesWithQhull) {
  std::mt19937_64 rng(11);
  int positive = 0;
  for (int trial = 0; trial < 200; ++trial) {
    GraspQualityRequest r = randomGrasp(3 + trial % 3, rng);
    r.cone_edges = trial % 2 == 0 ? 8 : 12;
    positive += compareWithQhull(r, trial);
  }
  EXPECT_GT(positive, 50);
}

// Many contacts: most wrenches never enter the incremental hull.
TEST(GraspQuality, IncrementalHullAgreesWithQhullForUpTo64Wrenches) {
  std::mt19937_64 rng(13);
  int positive = 0;
  for (int trial = 0; trial < 60; ++trial) {
    positive += compareWithQhull(randomGrasp(6 + trial % 3, rng), trial);
  }
  EXPECT_GT(positive, 20);
}

// Beyond 64 wrenches (ridges keyed by 12-bit indices): fine cones and
// many contacts, as a grasp.quality request may ask for.
TEST(GraspQuality, IncrementalHullAgreesWithQhullBeyond64Wrenches) {
  std::mt19937_64 rng(17);
  int positive = 0;
  for (int trial = 0; trial < 12; ++trial) {
    GraspQualityRequest r = randomGrasp(3 + trial % 2, rng);
    r.cone_edges = trial % 4 < 2 ? 24 : 32;  // 72 to 128 wrenches
    positive += compareWithQhull(r, trial);
  }
  EXPECT_GT(positive, 2);
}

TEST(GraspQuality, DegenerateGraspsGiveZeroWithoutErrors) {
  // Four contacts in one plane: a well-defined, finite value.
  GraspQualityRequest planar = equator({0, 90, 180, 270});
  EXPECT_GE(graspQuality(planar).epsilon, 0.0);
  // All contacts at one point: no torque can be resisted.
  GraspQualityRequest point = equator({0, 120, 240});
  for (Eigen::Index i = 0; i < 3; ++i) point.positions.col(i).setZero();
  EXPECT_EQ(graspQuality(point).epsilon, 0.0);
  // Many contacts (9 x 8 = 72 wrenches: the Qhull path).
  GraspQualityRequest many = equator({0, 40, 80, 120, 160, 200, 240, 280, 320});
  EXPECT_GT(graspQuality(many).epsilon, graspQuality(equator({0, 120, 240})).epsilon);
}

// Soft fingers (docs/grasp_quality.md): each contact also pushes a pure
// torsion of +-gamma about its normal. The reference adds those columns
// itself to the hard-finger wrenches and enumerates the facets by brute
// force, independent of both hulls and of the soft-finger code.
Eigen::Matrix<double, 6, Eigen::Dynamic> withTorsions(const GraspQualityRequest& soft) {
  GraspQualityRequest hard = soft;
  hard.torsional_friction = 0.0;
  const Eigen::Matrix<double, 6, Eigen::Dynamic> edges = contactWrenches(hard);
  const Eigen::Index n = soft.positions.cols();
  Eigen::Matrix<double, 6, Eigen::Dynamic> w(6, edges.cols() + 2 * n);
  w.leftCols(edges.cols()) = edges;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d normal = soft.normals.col(i);  // inward
    const Eigen::Vector3d torque =
        (soft.positions.col(i) - soft.center).cross(normal) / soft.torque_scale;
    const Eigen::Vector3d twist = soft.torsional_friction / soft.torque_scale * normal;
    w.col(edges.cols() + 2 * i) << normal, torque + twist;
    w.col(edges.cols() + 2 * i + 1) << normal, torque - twist;
  }
  return w;
}

TEST(GraspQuality, SoftFingersMatchAnIndependentReference) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.2, 1.0), gamma(0.001, 0.02);
  int positive = 0;
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 30; ++trial) {
    GraspQualityRequest r = randomGrasp(2 + trial % 2, rng);
    if (r.positions.cols() == 2) {  // nearly opposed, as a parallel-jaw gripper takes them
      const Eigen::Vector3d across =
          (-r.positions.col(0).normalized() + 0.15 * Eigen::Vector3d(g(rng), g(rng), g(rng)))
              .normalized();
      r.positions.col(1) = 0.05 * across;
      r.normals.col(1) = (-across + 0.1 * Eigen::Vector3d(g(rng), g(rng), g(rng))).normalized();
      r.normals.col(0) = -r.positions.col(0).normalized();
    }
    r.friction = u(rng);
    r.cone_edges = 4;
    r.torsional_friction = gamma(rng);
    const double expected = bruteForceEpsilon(withTorsions(r));
    const double actual = graspQuality(r).epsilon;
    EXPECT_NEAR(actual, expected, 1e-9 * std::max(expected, 1e-12)) << "trial " << trial;
    r.use_qhull = true;
    EXPECT_NEAR(graspQuality(r).epsilon, expected, 1e-9 * std::max(expected, 1e-12))
        << "trial " << trial;
    positive += expected > 0;
  }
  EXPECT_GT(positive, 10);
}

TEST(GraspQuality, TwoOpposedSoftFingersHoldWhereHardOnesCannot) {
  // A parallel-jaw grasp across a 5 cm sphere: hard point contacts cannot
  // resist a torque about the line through them; soft pads can.
  GraspQualityRequest r = equator({0, 180});
  r.positions *= 0.05;
  r.torque_scale = 0.05;
  EXPECT_EQ(graspQuality(r).epsilon, 0.0);
  double previous = 0.0;
  for (const double gamma : {0.001, 0.003, 0.01}) {
    r.torsional_friction = gamma;
    const double epsilon = graspQuality(r).epsilon;
    EXPECT_GT(epsilon, previous) << "gamma " << gamma;  // grows with the torsional friction
    EXPECT_NEAR(epsilon, bruteForceEpsilon(withTorsions(r)), 1e-9 * epsilon) << "gamma " << gamma;
    previous = epsilon;
  }
  // Three contacts: soft fingers only add wrenches, so epsilon cannot fall.
  GraspQualityRequest three = equator({0, 120, 240});
  const double hard = graspQuality(three).epsilon;
  three.torsional_friction = 0.05;
  EXPECT_GE(graspQuality(three).epsilon, hard);
}

TEST(GraspQuality, RejectsInvalidRequestsByField) {
  GraspQualityRequest r = equator({0, 120, 240});
  r.torsional_friction = -0.001;
  EXPECT_THROW(graspQuality(r), std::invalid_argument);
  r = equator({0, 120, 240});
  r.normals(0, 0) = 2.0;
  EXPECT_THROW(graspQuality(r), std::invalid_argument);
  r = equator({0, 120, 240});
  r.friction = 0.0;
  EXPECT_THROW(graspQuality(r), std::invalid_argument);
  r = equator({0, 120, 240});
  r.torque_scale = -1.0;
  EXPECT_THROW(graspQuality(r), std::invalid_argument);
  r = equator({0, 120, 240});
  r.cone_edges = 2;
  EXPECT_THROW(graspQuality(r), std::invalid_argument);
  r = equator({0, 120, 240});
  r.positions(1, 1) = std::nan("");
  EXPECT_THROW(graspQuality(r), std::invalid_argument);
  EXPECT_THROW(graspQuality(GraspQualityRequest{}), std::invalid_argument);
  // The library takes any number of wrenches (the contact masks ask about
  // hundreds of contacts); requests from outside are limited to
  // kMaxQualityWrenches (grasp_quality_json).
  r = equator({0, 72, 144, 216, 288});
  r.cone_edges = 64;
  EXPECT_GT(graspQuality(r).epsilon, 0.0);
}

// The slowest wrench sets of the largest size we know (contacts on a
// circle, 64 edges, high friction) stay within the facet budget. Their
// 64 edges include the 32 of the coarser cone, so epsilon cannot be
// smaller.
TEST(GraspQuality, TheWorstKnownLargeRequestsStayWithinTheHullBudget) {
  for (const double mu : {10.0, 100.0}) {
    GraspQualityRequest r = equator({0, 90, 180, 270});
    r.friction = mu;
    r.cone_edges = 32;
    const double coarse = graspQuality(r).epsilon;
    r.cone_edges = 64;
    const double fine = graspQuality(r).epsilon;
    EXPECT_GT(coarse, 0.5 * mu) << "mu " << mu;
    EXPECT_GE(fine, coarse * (1 - 1e-12)) << "mu " << mu;
  }
}

}  // namespace
}  // namespace hfts::grasp
