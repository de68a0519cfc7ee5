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

  SegmentCertificate certificate;
  certificate.clearance = std::numeric_limits<double>::infinity();
  double t = 0.0;
  Eigen::VectorXd q = a;
  while (true) {
    if (certificate.states == options.max_states) {
      certificate.exhausted = true;
      certificate.blocked_at = t;
      return certificate;
    }
    ++certificate.states;
    const double environment = checker.clearance(q);
    const double self = environment > 0.0 ? checker.selfClearance(q) : 0.0;
    const double nearest = std::min(environment, self);
    if (nearest < certificate.clearance) {
      certificate.clearance = nearest;
      certificate.at = t;
    }
    const double environmentSlack = environment - kDistanceTolerance - options.clearance;
    const double selfSlack = self - kDistanceTolerance - options.clearance;
    if (environmentSlack <= kBlockingSlack || selfSlack <= kBlockingSlack) {
      certificate.blocked_at = t;
      return certificate;
    }
    if (t >= 1.0 || step.isZero(0.0)) break;
    t = std::min(1.0, t + std::min(advance(environmentSlack, toEnvironment),
                                   advance(selfSlack, toEachOther)));
    q = t >= 1.0 ? b : Eigen::VectorXd(a + t * step);
  }
  certificate.free = true;
  return certificate;
}

}  // namespace hfts::robot
