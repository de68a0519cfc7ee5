// Separating-axis proofs (robot/src/shape_separation.h) against FCL's
// distance and against dense samples of the shapes.
#include "shape_separation.h"

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

namespace hfts::robot {
namespace {

constexpr double kGap = 1e-4;

/// A uniformly random rotation from `rng` (not Eigen's UnitRandom, which
/// draws from std::rand and so depends on what ran before in the process).
Eigen::Matrix3d randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  return q.normalized().toRotationMatrix();
}

PlacedShape randomShape(std::mt19937& rng, int type, double spread) {
  std::uniform_real_distribution<double> size(0.005, 0.08), at(-spread, spread);
  PlacedShape s;
  s.type = type;
  s.size = {size(rng), size(rng), size(rng)};
  s.rotation = randomRotation(rng);
  s.center = {at(rng), at(rng), at(rng)};
  return s;
}

std::shared_ptr<fcl::CollisionGeometryd> fclShape(const PlacedShape& s) {
  if (s.type == 0) return std::make_shared<fcl::Boxd>(s.size);
  if (s.type == 1) return std::make_shared<fcl::Cylinderd>(s.size.x(), s.size.y());
  return std::make_shared<fcl::Sphered>(s.size.x());
}

double fclDistance(const PlacedShape& a, const PlacedShape& b) {
  const fcl::CollisionObjectd oa(fclShape(a), a.rotation, a.center);
  const fcl::CollisionObjectd ob(fclShape(b), b.rotation, b.center);
  fcl::CollisionRequestd collisionRequest;
  fcl::CollisionResultd collisionResult;
  if (fcl::collide(&oa, &ob, collisionRequest, collisionResult) > 0) return 0.0;
  fcl::DistanceRequestd request;
  fcl::DistanceResultd result;
  return fcl::distance(&oa, &ob, request, result);
}

/// Points of the shape's surface and interior, in the world.
std::vector<Eigen::Vector3d> samples(const PlacedShape& s, std::mt19937& rng, int count) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  // Where supports are attained: the box's corners, the cylinder's rims.
  if (s.type == 0)
    for (int c = 0; c < 8; ++c)
      points.push_back(s.center + s.rotation * Eigen::Vector3d(c & 1 ? 0.5 : -0.5,
                                                               c & 2 ? 0.5 : -0.5,
                                                               c & 4 ? 0.5 : -0.5)
                                                   .cwiseProduct(s.size));
  if (s.type == 1)
    for (int k = 0; k < 720; ++k) {
      const double angle = k * M_PI / 360.0, z = k % 2 == 0 ? 0.5 : -0.5;
      points.push_back(s.center + s.rotation * Eigen::Vector3d(s.size.x() * std::cos(angle),
                                                               s.size.x() * std::sin(angle),
                                                               z * s.size.y()));
    }
  while (static_cast<int>(points.size()) < count) {
    Eigen::Vector3d u(unit(rng), unit(rng), unit(rng));
    // Push half of them to the boundary (one coordinate, or the radius, at 1).
    const bool boundary = points.size() % 2 == 0;
    Eigen::Vector3d local;
    if (s.type == 0) {
      if (boundary) u(static_cast<Eigen::Index>(points.size() / 2 % 3)) = u.x() < 0 ? -1 : 1;
      local = u.cwiseProduct(0.5 * s.size);
    } else if (s.type == 1) {
      Eigen::Vector2d disc(u.x(), u.y());
      if (disc.norm() > 1.0) continue;
      if (boundary) disc.normalize();
      local = {s.size.x() * disc.x(), s.size.x() * disc.y(), 0.5 * s.size.y() * u.z()};
    } else {
      if (u.norm() > 1.0) continue;
      if (boundary) u.normalize();
      local = s.size.x() * u;
    }
    points.push_back(s.center + s.rotation * local);
  }
  return points;
}

TEST(ShapeSeparation, SupportIsTheMaximumOverTheShape) {
  std::mt19937 rng(3);
  for (int type = 0; type < 3; ++type) {
    for (int trial = 0; trial < 20; ++trial) {
      const PlacedShape s = randomShape(rng, type, 0.2);
      const std::vector<Eigen::Vector3d> points = samples(s, rng, 4000);
      for (int d = 0; d < 10; ++d) {
        std::uniform_real_distribution<double> component(-3.0, 3.0);
        const Eigen::Vector3d n(component(rng), component(rng), component(rng));
        double most = -1e9;
        for (const Eigen::Vector3d& p : points) most = std::max(most, n.dot(p));
        const double bound = support(s, n);
        EXPECT_GE(bound, most - 1e-12) << "type " << type;  // no sample beyond it
        EXPECT_LE(bound, most + 0.02 * n.norm() * s.size.maxCoeff()) << "type " << type;
      }
    }
  }
}

TEST(ShapeSeparation, ClosestPointsOfSegmentsMatchDenseSampling) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> at(-1.0, 1.0);
  for (int trial = 0; trial < 300; ++trial) {
    const auto point = [&] { return Eigen::Vector3d(at(rng), at(rng), at(rng)); };
    const Eigen::Vector3d p0 = point(), q0 = point();
    // Some degenerate (point) and some parallel segments among them.
    const Eigen::Vector3d p1 = trial % 7 == 0 ? p0 : point();
    const Eigen::Vector3d q1 =
        trial % 5 == 0 ? q0 : (trial % 11 == 0 ? q0 + (p1 - p0) * 0.7 : point());
    Eigen::Vector3d onP, onQ;
    const double squared = closestPointsOfSegments(p0, p1, q0, q1, onP, onQ);
    EXPECT_NEAR(squared, (onP - onQ).squaredNorm(), 1e-12);
    double best = 1e9;
    for (int i = 0; i <= 200; ++i)
      for (int j = 0; j <= 200; ++j)
        best = std::min(best, (p0 + (p1 - p0) * (i / 200.0) - q0 - (q1 - q0) * (j / 200.0)).norm());
    EXPECT_LE(std::sqrt(squared), best + 1e-12);
    EXPECT_GE(std::sqrt(squared), best - 0.02);  // the grid's own error
  }
}

TEST(ShapeSeparation, NeverCallsAPairApartThatFclFindsWithinTheGap) {
  std::mt19937 rng(7);
  int proven = 0, apartByACentimetre = 0, provenOfThose = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const PlacedShape a = randomShape(rng, trial % 3, 0.1);
    const PlacedShape b = randomShape(rng, trial / 3 % 3, 0.1);
    const double distance = fclDistance(a, b);
    const bool apart = provablyApart(a, b, kGap);
    if (apart) {
      ++proven;
      EXPECT_GT(distance, kGap - 1e-9) << "trial " << trial;
    }
    if (distance > 0.01) {
      ++apartByACentimetre;
      if (apart) ++provenOfThose;
    }
  }
  EXPECT_GT(proven, 1000);
  // Not complete for curved shapes, but most pairs a centimetre apart are proven.
  EXPECT_GT(provenOfThose, 0.9 * apartByACentimetre);
}

TEST(ShapeSeparation, BoxesApartAreAlwaysProvenApart) {
  // Faces and edge-pair directions are every separating axis two boxes have.
  std::mt19937 rng(11);
  int checked = 0;
  for (int trial = 0; trial < 5000; ++trial) {
    const PlacedShape a = randomShape(rng, 0, 0.08), b = randomShape(rng, 0, 0.08);
    if (fclDistance(a, b) <= 2 * kGap) continue;
    ++checked;
    EXPECT_TRUE(provablyApart(a, b, kGap)) << "trial " << trial;
  }
  EXPECT_GT(checked, 500);
}

TEST(ShapeSeparation, SpheresApartAreAlwaysProvenApart) {
  // The direction from the other shape's nearest point to the centre.
  std::mt19937 rng(13);
  int checked = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const PlacedShape a = randomShape(rng, 2, 0.1), b = randomShape(rng, trial % 3, 0.1);
    if (fclDistance(a, b) <= 2 * kGap) continue;
    ++checked;
    EXPECT_TRUE(provablyApart(a, b, kGap)) << "trial " << trial;
    EXPECT_TRUE(provablyApart(b, a, kGap)) << "trial " << trial;
  }
  EXPECT_GT(checked, 1000);
}

TEST(ShapeSeparation, ParallelCylindersSideBySideOrEndToEndAreProvenApart) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> size(0.005, 0.08), gap(2 * kGap, 0.02), along(-0.5, 0.5);
  for (int trial = 0; trial < 500; ++trial) {
    PlacedShape a, b;
    a.type = b.type = 1;
    a.size = {size(rng), size(rng), 0.0};
    b.size = {size(rng), size(rng), 0.0};
    a.rotation = b.rotation = randomRotation(rng);
    const Eigen::Vector3d axis = a.rotation.col(2), across = a.rotation.col(0);
    a.center = Eigen::Vector3d::Zero();
    if (trial % 2 == 0)  // side by side, overlapping along the axis
      b.center = across * (a.size.x() + b.size.x() + gap(rng)) +
                 axis * along(rng) * std::min(a.size.y(), b.size.y());
    else  // end to end on one axis
      b.center = axis * (0.5 * (a.size.y() + b.size.y()) + gap(rng));
    EXPECT_TRUE(provablyApart(a, b, kGap)) << "trial " << trial;
  }
}

TEST(ShapeSeparation, TouchingShapesAreNotProvenApart) {
  PlacedShape a, b;
  a.type = b.type = 1;
  a.size = b.size = {0.014, 0.08, 0.0};
  b.center = {0.028, 0.0, 0.0};  // two finger cylinders side by side, touching
  EXPECT_FALSE(provablyApart(a, b, kGap));
  b.center.x() = 0.028 + 2 * kGap;
  EXPECT_TRUE(provablyApart(a, b, kGap));
  b.center.x() = 0.028 + 0.5 * kGap;
  EXPECT_FALSE(provablyApart(a, b, kGap));
}

}  // namespace
}  // namespace hfts::robot
