#include "robot/segment_certificate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

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
  // How far any link, and any two links towards each other, move over the
  // whole segment at most.
  const double toEnvironment = bound.anyLink(step);
  const double toEachOther = bound.anyTwoLinks(step);
  auto advance = [](double slack, double perSegment) {
    return perSegment > 0.0 ? slack / perSegment : std::numeric_limits<double>::infinity();
  };

  // The segment is proven up to `environmentUntil` against the environment
  // and up to `selfUntil` against the robot's own links; each distance is
  // measured again only where its own proof ends.
  SegmentCertificate certificate;
  certificate.clearance = std::numeric_limits<double>::infinity();
  double environmentUntil = 0.0, selfUntil = 0.0;
  const bool still = step.isZero(0.0);
  while (std::min(environmentUntil, selfUntil) < 1.0 || certificate.queries == 0) {
    const double t = std::min(environmentUntil, selfUntil);
    if (certificate.queries >= options.max_queries) {
      certificate.exhausted = true;
      certificate.blocked_at = t;
      return certificate;
    }
    const Eigen::VectorXd q = t >= 1.0 ? b : Eigen::VectorXd(a + t * step);
    const bool environmentDue = environmentUntil <= t;
    const double distance = environmentDue ? checker.clearance(q) : checker.selfClearance(q);
    ++certificate.queries;
    certificate.self_queries += environmentDue ? 0 : 1;
    if (distance < certificate.clearance) {
      certificate.clearance = distance;
      certificate.at = t;
    }
    const double slack = distance - kDistanceTolerance - options.clearance;
    if (slack <= kBlockingSlack) {
      certificate.blocked_at = t;
      return certificate;
    }
    double& until = environmentDue ? environmentUntil : selfUntil;
    until = still ? 1.0
                  : std::min(1.0, t + advance(slack, environmentDue ? toEnvironment : toEachOther));
  }
  certificate.free = true;
  return certificate;
}

}  // namespace hfts::robot
