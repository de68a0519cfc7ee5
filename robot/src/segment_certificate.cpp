#include "robot/segment_certificate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "core/invalid_argument.h"

namespace hfts::robot {
namespace {

/// Taken off every distance FCL reports before it counts as slack: FCL's
/// distances between primitives come from an iterative solver (GJK) that
/// stops within 1e-6 m, so a reported distance may exceed the true one by
/// that much.
constexpr double kDistanceTolerance = 1e-5;
/// A state closer than the clearance plus this (m) blocks the segment:
/// advancing towards a contact only approaches it (each step is the
/// remaining slack over the bound), so the slack must run out at a
/// distance, not at zero.
constexpr double kBlockingSlack = 1e-4;

}  // namespace

SegmentCertificate certifySegment(CollisionChecker& checker, const MotionBound& bound,
                                  const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                                  const CertifyOptions& options) {
  if (!std::isfinite(options.clearance) || options.clearance < 0.0)
    throw InvalidArgument("clearance", "must be a finite distance >= 0 (m), not " +
                                           std::to_string(options.clearance));
  const int dofs = checker.model().numDofs();
  if (a.size() != dofs || b.size() != dofs || !a.allFinite() || !b.allFinite())
    throw InvalidArgument("segment",
                          "ends must be " + std::to_string(dofs) + " finite joint values each");
  const Eigen::VectorXd step = b - a;
  const bool still = step.isZero(0.0);
  const RobotModel& model = checker.model();
  // The links with shapes, and how far each moves over the whole segment
  // at most; how much closer any two links can come.
  std::vector<int> links;
  std::vector<double> travel;
  for (std::size_t l = 0; l < model.links().size(); ++l)
    if (!model.links()[l].shapes.empty()) {
      links.push_back(static_cast<int>(l));
      travel.push_back(bound.link(static_cast<int>(l), step));
    }
  // The link pairs that may collide, and how much closer each can come.
  std::vector<std::pair<int, int>> pairs;
  std::vector<double> closing;
  for (std::size_t i = 0; i < links.size(); ++i)
    for (std::size_t k = i + 1; k < links.size(); ++k)
      if (!model.isCollisionDisabled(links[i], links[k])) {
        pairs.emplace_back(links[i], links[k]);
        closing.push_back(bound.pair(links[i], links[k], step));
      }
  auto advance = [&](double t, double slack, double perSegment) {
    return still || perSegment <= 0.0 ? 1.0 : std::min(1.0, t + slack / perSegment);
  };

  // Each link is proven against the environment up to its own `until`,
  // each pair of links against each other up to its `pairUntil`; a
  // distance is measured again only where its proof ends.
  SegmentCertificate certificate;
  certificate.clearance = std::numeric_limits<double>::infinity();
  std::vector<double> until(links.size(), 0.0), pairUntil(pairs.size(), 0.0), distances;
  std::vector<int> due;
  std::vector<std::pair<int, int>> duePairs;
  auto measured = [&](double distance, double t, int link, int other) {
    if (distance < certificate.clearance) {
      certificate.clearance = distance;
      certificate.at = t;
      certificate.nearest_link = link;
      certificate.nearest_other_link = other;
    }
    return distance - kDistanceTolerance - options.clearance;
  };
  auto earliest = [](const std::vector<double>& v) {
    return v.empty() ? 1.0 : *std::min_element(v.begin(), v.end());
  };
  while (true) {
    const double t = std::min(earliest(until), earliest(pairUntil));
    if (t >= 1.0 && certificate.queries > 0) break;
    if (certificate.queries >= options.max_queries) {
      certificate.exhausted = true;
      certificate.blocked_at = t;
      return certificate;
    }
    const Eigen::VectorXd q = t >= 1.0 ? b : Eigen::VectorXd(a + t * step);
    due.clear();
    for (std::size_t k = 0; k < links.size(); ++k)
      if (until[k] <= t) due.push_back(links[k]);
    if (!due.empty()) {
      checker.linkClearances(q, due, distances);
      certificate.queries += due.size();
      for (std::size_t k = 0, d = 0; k < links.size(); ++k) {
        if (until[k] > t) continue;
        const double slack = measured(distances[d++], t, links[k], -1);
        if (slack <= kBlockingSlack) {
          certificate.blocked_at = t;
          return certificate;
        }
        until[k] = advance(t, slack, travel[k]);
      }
    }
    duePairs.clear();
    for (std::size_t k = 0; k < pairs.size(); ++k)
      if (pairUntil[k] <= t) duePairs.push_back(pairs[k]);
    if (!duePairs.empty()) {
      checker.pairClearances(q, duePairs, distances);
      certificate.queries += duePairs.size();
      certificate.self_queries += duePairs.size();
      for (std::size_t k = 0, d = 0; k < pairs.size(); ++k) {
        if (pairUntil[k] > t) continue;
        const double slack = measured(distances[d++], t, pairs[k].first, pairs[k].second);
        if (slack <= kBlockingSlack) {
          certificate.blocked_at = t;
          return certificate;
        }
        pairUntil[k] = advance(t, slack, closing[k]);
      }
    }
  }
  certificate.free = true;
  return certificate;
}

}  // namespace hfts::robot
