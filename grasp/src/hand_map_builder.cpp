// Building the hand reachability map: seeded sampling of the hand joint
// space, the grasp-posture test and the m-finger descriptor
// (docs/hand_reachability.md).

#include "grasp/hand_map_builder.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "core/invalid_argument.h"
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

/// Distance from the origin to the tetrahedron (a, b, c, d): 0 inside (the
/// origin on the same side of every face as the opposite vertex), else the
/// nearest face's.
double distanceToOrigin(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                        const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  const auto sameSide = [](const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                           const Eigen::Vector3d& r, const Eigen::Vector3d& opposite) {
    const Eigen::Vector3d normal = (q - p).cross(r - p);
    return normal.dot(opposite - p) * normal.dot(-p) >= 0.0;
  };
  const double volume = (b - a).cross(c - a).dot(d - a);
  if (std::abs(volume) > 1e-12 && sameSide(a, b, c, d) && sameSide(a, b, d, c) &&
      sameSide(a, c, d, b) && sameSide(b, c, d, a))
    return 0.0;
  return std::min({distanceToOrigin(a, b, c), distanceToOrigin(a, b, d), distanceToOrigin(a, c, d),
                   distanceToOrigin(b, c, d)});
}

/// Distance from the origin to the convex hull of the columns (2..4).
double distanceToOrigin(const FingerColumns& points) {
  switch (points.cols()) {
    case 2:
      return closestOnSegment(points.col(0), points.col(1)).norm();
    case 3:
      return distanceToOrigin(points.col(0), points.col(1), points.col(2));
    default:
      return distanceToOrigin(points.col(0), points.col(1), points.col(2), points.col(3));
  }
}

void checkFingers(Eigen::Index fingers) {
  if (fingers < robot::hand::kMinFingers || fingers > robot::hand::kMaxFingers)
    throw InvalidArgument("fingers", "must be in " + std::to_string(robot::hand::kMinFingers) +
                                         ".." + std::to_string(robot::hand::kMaxFingers) +
                                         ", got " + std::to_string(fingers));
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
  map.descriptor = handDescriptorName(chains.numFingers());
  map.parameters = options;
  return map;
}

/// Row-major N x cols matrix from concatenated rows.
db::RowMatrixXd rows(const std::vector<double>& data, Eigen::Index cols) {
  return Eigen::Map<const db::RowMatrixXd>(data.data(),
                                           static_cast<Eigen::Index>(data.size()) / cols, cols);
}

}  // namespace

const char* handDescriptorName(int fingers) {
  checkFingers(fingers);
  constexpr const char* kNames[] = {"pair-distance-normals-5", "triangle-edges-normals-12",
                                    "quadrilateral-edges-diagonals-normals-18"};
  return kNames[fingers - 2];
}

int handDescriptorSize(int fingers) {
  checkFingers(fingers);
  constexpr int kSizes[] = {5, 12, 18};
  return kSizes[fingers - 2];
}

bool isGraspPosture(const FingerColumns& positions, const FingerColumns& padNormals,
                    const HandMapOptions& options) {
  const Eigen::Index m = positions.cols();
  checkFingers(m);
  const Eigen::Vector3d sum = positions.rowwise().sum();
  for (Eigen::Index i = 0; i < m; ++i) {
    for (Eigen::Index j = i + 1; j < m; ++j)
      if ((positions.col(j) - positions.col(i)).norm() < options.min_fingertip_distance)
        return false;
    const Eigen::Vector3d towardsOthers =
        (sum - positions.col(i)) / static_cast<double>(m - 1) - positions.col(i);
    if (padNormals.col(i).dot(towardsOthers) <= 0.0) return false;
  }
  // Friction cones of half-angle atan(mu) around the pad normals can cancel.
  const double reach = options.friction / std::sqrt(1.0 + options.friction * options.friction);
  return distanceToOrigin(padNormals) <= reach;
}

namespace {

/// m = 2: the distance, the pads' components along the line through the
/// fingertips and the dihedral angle between them about it.
void pairDescriptor(const FingerColumns& positions, const FingerColumns& pads, double weight,
                    HandDescriptor& d) {
  const Eigen::Vector3d e = positions.col(1) - positions.col(0);
  const Eigen::Vector3d u = unitOrZero(e);
  const double a0 = pads.col(0).dot(u), a1 = pads.col(1).dot(u);
  const Eigen::Vector3d t0 = pads.col(0) - a0 * u, t1 = pads.col(1) - a1 * u;
  d << e.norm(), weight * a0, weight * a1, weight * t0.dot(t1), weight * u.dot(t0.cross(t1));
}

/// m >= 3: cyclic edges (and the diagonals of four), then each pad in the
/// frame of its finger's two cyclic successors.
void polygonDescriptor(const FingerColumns& positions, const FingerColumns& pads, double weight,
                       HandDescriptor& d) {
  const Eigen::Index m = positions.cols();
  const Eigen::Index edges = m == 4 ? 6 : m;
  for (Eigen::Index i = 0; i < m; ++i) {
    const Eigen::Index j = (i + 1) % m, k = (i + 2) % m;
    const Eigen::Vector3d eij = positions.col(j) - positions.col(i);
    const Eigen::Vector3d uij = unitOrZero(eij);
    const Eigen::Vector3d uik = unitOrZero(positions.col(k) - positions.col(i));
    const Eigen::Vector3d n = pads.col(i);
    d(i) = eij.norm();
    d.segment<3>(edges + 3 * i) << n.dot(uij), n.dot(uik), n.dot(uij.cross(uik));
  }
  if (m == 4) {
    d(4) = (positions.col(2) - positions.col(0)).norm();
    d(5) = (positions.col(3) - positions.col(1)).norm();
  }
  d.tail(3 * m) *= weight;
}

}  // namespace

HandDescriptor handDescriptor(const FingerColumns& positions, const FingerColumns& padNormals,
                              double normalWeight) {
  const auto m = static_cast<int>(positions.cols());
  HandDescriptor d(handDescriptorSize(m));
  if (m == 2)
    pairDescriptor(positions, padNormals, normalWeight, d);
  else
    polygonDescriptor(positions, padNormals, normalWeight, d);
  return d;
}

HandMapOptions handMapOptions(const robot::RobotModel& model) {
  HandMapOptions options;
  if (model.handMapNormalWeight() > 0.0) options.normal_weight = model.handMapNormalWeight();
  return options;
}

db::HandMap buildHandMap(const robot::RobotModel& model, const HandMapOptions& options) {
  checkOptions(options);
  if (!model.hasHand())
    throw robot::ModelError("robot '" + model.name() +
                            "' has no hand (no hand_joints, no fingertips): it needs no hand map");
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
    positions.insert(positions.end(), tips.positions.data(),
                     tips.positions.data() + tips.positions.size());
    normals.insert(normals.end(), tips.normals.data(), tips.normals.data() + tips.normals.size());
    descriptors.insert(descriptors.end(), descriptor.data(), descriptor.data() + descriptor.size());
  }
  if (configurations.empty())
    throw robot::ModelError(model.name() + ": no grasp posture in " +
                            std::to_string(map.num_draws) + " random hand configurations");
  map.configurations = rows(configurations, dofs);
  const Eigen::Index columns = 3 * chains.numFingers();
  map.positions = rows(positions, columns);
  map.normals = rows(normals, columns);
  map.descriptors = rows(descriptors, handDescriptorSize(chains.numFingers()));
  return map;
}

}  // namespace hfts::grasp
