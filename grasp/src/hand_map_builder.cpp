// Building the hand reachability map: seeded sampling of the hand joint
// space, the grasp-posture test and the triple descriptor
// (docs/hand_reachability.md).

#include "grasp/hand_map_builder.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "hfts_db/invalid_argument.h"
#include "robot/hand_chain.h"

namespace hfts::grasp {
namespace {

Eigen::Vector3d closestOnSegment(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double length2 = ab.squaredNorm();
  if (length2 < 1e-24) return a;
  return a + std::clamp(-a.dot(ab) / length2, 0.0, 1.0) * ab;
}

/// Distance from the origin to the triangle (a, b, c): the smallest
/// resultant of unit forces along a, b and c with weights summing to one.
double distanceToOrigin(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                        const Eigen::Vector3d& c) {
  double best = std::min({closestOnSegment(a, b).norm(), closestOnSegment(b, c).norm(),
                          closestOnSegment(c, a).norm()});
  const Eigen::Vector3d normal = (b - a).cross(c - a);
  const double area2 = normal.squaredNorm();
  if (area2 < 1e-24) return best;
  // The origin's projection lies inside when it is on the inner side of all edges.
  const Eigen::Vector3d p = (a.dot(normal) / area2) * normal;
  const bool inside = (b - a).cross(p - a).dot(normal) >= 0 &&
                      (c - b).cross(p - b).dot(normal) >= 0 &&
                      (a - c).cross(p - c).dot(normal) >= 0;
  if (inside) best = std::min(best, p.norm());
  return best;
}

Eigen::Vector3d unitOrZero(const Eigen::Vector3d& v) {
  const double length = v.norm();
  return length > 1e-12 ? Eigen::Vector3d(v / length) : Eigen::Vector3d::Zero();
}

void checkOptions(const HandMapOptions& o) {
  if (o.num_samples == 0) throw InvalidArgument("HandMapOptions::num_samples", "must be > 0");
  if (o.max_draws < o.num_samples)
    throw InvalidArgument("HandMapOptions::max_draws", "must be >= num_samples");
  if (!(o.normal_weight > 0.0) || !std::isfinite(o.normal_weight))
    throw InvalidArgument("HandMapOptions::normal_weight",
                          "must be positive, got " + std::to_string(o.normal_weight));
  if (!(o.min_fingertip_distance >= 0.0) || !std::isfinite(o.min_fingertip_distance))
    throw InvalidArgument("HandMapOptions::min_fingertip_distance", "must be >= 0");
  if (!(o.friction >= 0.0) || !std::isfinite(o.friction))
    throw InvalidArgument("HandMapOptions::friction", "must be >= 0");
}

/// Uniform in [0, 1) from 53 random bits: the same on every platform,
/// unlike std::uniform_real_distribution.
double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

/// Radical inverse of i in a prime base: the Halton sequence, which covers
/// the joint space more evenly than independent draws (fewer holes, so
/// fewer triples whose nearest samples are all far away).
double radicalInverse(std::uint64_t i, std::uint64_t base) {
  double result = 0.0, scale = 1.0 / static_cast<double>(base);
  for (; i > 0; i /= base, scale /= static_cast<double>(base))
    result += static_cast<double>(i % base) * scale;
  return result;
}

constexpr std::uint64_t kPrimes[robot::hand::kMaxDofs] = {2,  3,  5,  7,  11, 13, 17, 19,
                                                          23, 29, 31, 37, 41, 43, 47, 53};

/// Point `index` of the Halton sequence shifted by `shift` (Cranley-Patterson
/// rotation: the seed moves the sequence), scaled into the joint limits.
void haltonConfiguration(std::uint64_t index, const robot::hand::HandVector& shift,
                         const robot::hand::HandChains& chains, robot::hand::HandVector& q) {
  for (Eigen::Index d = 0; d < q.size(); ++d) {
    const double u = radicalInverse(index, kPrimes[d]) + shift(d);
    q(d) = chains.lower()(d) + (u - std::floor(u)) * (chains.upper()(d) - chains.lower()(d));
  }
}

db::HandMap emptyMap(const robot::RobotModel& model, const robot::hand::HandChains& chains,
                     const HandMapOptions& options) {
  db::HandMap map;
  map.robot_name = model.name();
  map.producer = "hfts::grasp::buildHandMap";
  map.dof_names = chains.dofNames();
  map.lower_limits = chains.lower();
  map.upper_limits = chains.upper();
  map.finger_names = chains.fingerNames();
  map.descriptor = kHandDescriptorName;
  map.parameters = options;
  return map;
}

/// Row-major N x cols matrix from concatenated rows.
db::RowMatrixXd rows(const std::vector<double>& data, Eigen::Index cols) {
  return Eigen::Map<const db::RowMatrixXd>(data.data(),
                                           static_cast<Eigen::Index>(data.size()) / cols, cols);
}

}  // namespace

bool isGraspPosture(const Eigen::Matrix3d& positions, const Eigen::Matrix3d& padNormals,
                    const HandMapOptions& options) {
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    if ((positions.col(j) - positions.col(i)).norm() < options.min_fingertip_distance) return false;
    const Eigen::Vector3d towardsOthers =
        0.5 * (positions.col(j) + positions.col(k)) - positions.col(i);
    if (padNormals.col(i).dot(towardsOthers) <= 0.0) return false;
  }
  // Friction cones of half-angle atan(mu) around the pad normals can cancel.
  const double reach = options.friction / std::sqrt(1.0 + options.friction * options.friction);
  return distanceToOrigin(padNormals.col(0), padNormals.col(1), padNormals.col(2)) <= reach;
}

Eigen::Matrix<double, kHandDescriptorSize, 1> handDescriptor(const Eigen::Matrix3d& positions,
                                                             const Eigen::Matrix3d& padNormals,
                                                             double normalWeight) {
  Eigen::Matrix<double, kHandDescriptorSize, 1> d;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const Eigen::Vector3d eij = positions.col(j) - positions.col(i);
    const Eigen::Vector3d uij = unitOrZero(eij);
    const Eigen::Vector3d uik = unitOrZero(positions.col(k) - positions.col(i));
    const Eigen::Vector3d n = padNormals.col(i);
    d(i) = eij.norm();
    d.segment<3>(3 + 3 * i) << n.dot(uij), n.dot(uik), n.dot(uij.cross(uik));
  }
  d.tail<9>() *= normalWeight;
  return d;
}

db::HandMap buildHandMap(const robot::RobotModel& model, const HandMapOptions& options) {
  checkOptions(options);
  const robot::hand::HandChains chains(model);
  db::HandMap map = emptyMap(model, chains, options);
  const int dofs = chains.numDofs();
  std::vector<double> configurations, positions, normals, descriptors;
  std::mt19937_64 rng(options.seed);
  robot::hand::HandVector shift(dofs);
  for (int d = 0; d < dofs; ++d) shift(d) = uniform01(rng);
  robot::hand::TipState tips;
  robot::hand::HandVector q(dofs);
  while (map.num_draws < options.max_draws &&
         configurations.size() <
             std::size_t{options.num_samples} * static_cast<std::size_t>(dofs)) {
    haltonConfiguration(++map.num_draws, shift, chains, q);
    chains.evaluate(q.data(), tips, false);
    if (!isGraspPosture(tips.positions, tips.normals, options)) continue;
    const auto descriptor = handDescriptor(tips.positions, tips.normals, options.normal_weight);
    configurations.insert(configurations.end(), q.data(), q.data() + dofs);
    positions.insert(positions.end(), tips.positions.data(), tips.positions.data() + 9);
    normals.insert(normals.end(), tips.normals.data(), tips.normals.data() + 9);
    descriptors.insert(descriptors.end(), descriptor.data(), descriptor.data() + descriptor.size());
  }
  if (configurations.empty())
    throw robot::ModelError(model.name() + ": no grasp posture in " +
                            std::to_string(map.num_draws) + " random hand configurations");
  map.configurations = rows(configurations, dofs);
  map.positions = rows(positions, 9);
  map.normals = rows(normals, 9);
  map.descriptors = rows(descriptors, kHandDescriptorSize);
  return map;
}

}  // namespace hfts::grasp
