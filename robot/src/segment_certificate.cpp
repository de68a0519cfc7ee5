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
/// distances come from an iterative solver (GJK, tolerance 1e-6 m), and
/// the same pair asked through the broadphase and directly has differed by
/// 5e-6 m (segment_certificate_test), so a reported distance may exceed
/// the true one by about that much.
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
  // A proof per link with shapes against the environment (other -1) and
  // per link pair that may collide, each with how far its link moves (or
  // its links come closer) over the whole segment at most. Each holds up
  // to its own `until`; its distance is measured again only there.
  struct Proof {
    int link = -1, other = -1;
    double travel = 0.0, until = 0.0;
  };
  std::vector<Proof> proofs;
  std::vector<int> links;
  for (std::size_t l = 0; l < model.links().size(); ++l)
    if (!model.links()[l].shapes.empty()) links.push_back(static_cast<int>(l));
  for (const int link : links) proofs.push_back({link, -1, bound.link(link, step)});
  for (std::size_t i = 0; i < links.size(); ++i)
    for (std::size_t k = i + 1; k < links.size(); ++k)
      if (!model.isCollisionDisabled(links[i], links[k]))
        proofs.push_back({links[i], links[k], bound.pair(links[i], links[k], step)});

  SegmentCertificate certificate;
  certificate.clearance = std::numeric_limits<double>::infinity();
  std::vector<int> dueLinks;
  std::vector<std::pair<int, int>> duePairs;
  std::vector<double> linkDistances, pairDistances;
  while (true) {
    double t = 1.0;
    for (const Proof& proof : proofs) t = std::min(t, proof.until);
    if (t >= 1.0) break;  // every proof reaches b (or the robot has no shapes)
    if (certificate.queries >= options.max_queries) {
      certificate.exhausted = true;
      certificate.blocked_at = t;
      return certificate;
    }
    const Eigen::VectorXd q = t >= 1.0 ? b : Eigen::VectorXd(a + t * step);
    dueLinks.clear();
    duePairs.clear();
    for (const Proof& proof : proofs)
      if (proof.until <= t) {
        if (proof.other < 0)
          dueLinks.push_back(proof.link);
        else
          duePairs.emplace_back(proof.link, proof.other);
      }
    checker.linkClearances(q, dueLinks, linkDistances);
    checker.pairClearances(q, duePairs, pairDistances);
    certificate.queries += dueLinks.size() + duePairs.size();
    certificate.self_queries += duePairs.size();
    std::size_t nextLink = 0, nextPair = 0;
    for (Proof& proof : proofs) {
      if (proof.until > t) continue;
      const double distance =
          proof.other < 0 ? linkDistances[nextLink++] : pairDistances[nextPair++];
      if (distance < certificate.clearance) {
        certificate.clearance = distance;
        certificate.at = t;
        certificate.nearest_link = proof.link;
        certificate.nearest_other_link = proof.other;
      }
      const double slack = distance - kDistanceTolerance - options.clearance;
      if (slack <= kBlockingSlack) {
        certificate.blocked_at = t;
        return certificate;
      }
      proof.until = still || proof.travel <= 0.0 ? 1.0 : std::min(1.0, t + slack / proof.travel);
    }
  }
  certificate.free = true;
  return certificate;
}

}  // namespace hfts::robot
