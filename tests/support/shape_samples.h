#pragma once
// Random points on a robot link's collision primitives, for tests that check
// geometry against a bound.

#include <cmath>
#include <random>

#include "robot/robot_model.h"

namespace hfts::test {

/// A point on the surface of `s` (link frame), uniform per face or side.
inline Eigen::Vector3d surfacePoint(const robot::CollisionShape& s, std::mt19937_64& rng) {
  using Shape = robot::CollisionShape::Type;
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Vector3d p;
  if (s.type == Shape::kSphere) {
    p = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized() * s.size[0];
  } else if (s.type == Shape::kBox) {
    p = Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(s.size / 2);
    const int axis = std::uniform_int_distribution<int>(0, 2)(rng);
    p[axis] = (u(rng) < 0 ? -0.5 : 0.5) * s.size[axis];
  } else {
    const double angle = M_PI * u(rng), half = s.size[1] / 2;
    if (u(rng) < 0) {  // side
      p << s.size[0] * std::cos(angle), s.size[0] * std::sin(angle), half * u(rng);
    } else {  // a cap
      const double r = s.size[0] * std::sqrt(std::abs(u(rng)));
      p << r * std::cos(angle), r * std::sin(angle), u(rng) < 0 ? -half : half;
    }
  }
  return s.origin * p;
}

}  // namespace hfts::test
