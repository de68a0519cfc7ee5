#include "robot/segment_certificate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "core/invalid_argument.h"

namespace hfts::robot {
namespace {

/// Taken off every distance FCL reports before it counts as slack: FCL's
/// distances come from an iterative solver (GJK, tolerance 1e-6 m), and
/// the same pair asked through the broadphase and directly has differed by
/// 5e-6 m (segment_certificate_test), so a reported distance may exceed
/// the true one by about that much.
constexpr double kDistanceTolerance = 1e-5;
/// A state closer than what the rule asks plus this (m) blocks the
/// motion: advancing towards a contact only approaches it (each step is
/// the remaining slack over the bound), so the slack must run out at a
/// distance, not at zero.
constexpr double kBlockingSlack = 1e-4;
/// A mesh (the target, a mesh obstacle) is measured exactly only within
/// the clearance plus this (m) of its bounding box; farther, the box's
/// distance (a lower bound, a fraction of the cost) proves as much.
constexpr double kExactBeyondClearance = 0.02;

/// What one proof measures. A link's distances to the obstacles and to the
/// target are proven apart: the target's mesh costs far more to measure
/// than the obstacles' primitives, and each is measured again only where
/// its own proof ends.
enum class Against {
  kObstacles,  ///< a link to the obstacles
  kTarget,     ///< a link to the target (none for a fingertip closing on it)
  kLink,       ///< a link to another link
};

/// How far a proof's distance must stay.
enum class Keeps {
  kClearance,  ///< the clearance asked
  kFree,       ///< only free (0 plus the blocking slack)
  kArriving,   ///< the clearance, shrinking to 0 over the link's last approach_length of travel
};

/// One distance that holds over a stretch of the motion: a link against
/// the environment, or a link pair. Its distance is measured again only
/// where its proof ends (`until`, as a motion position k + t).
struct Proof {
  int link = -1, other = -1;
  Against against = Against::kObstacles;
  Keeps keeps = Keeps::kClearance;
  std::vector<double> travel;     ///< per segment: how far it can come closer, at most (m)
  std::vector<double> remaining;  ///< kArriving: travel from waypoint k to the end
  double until = 0.0;
  /// Counts towards the reported clearance: not a pair whose distance is
  /// the robot's (two links that do not move relative to each other).
  bool reported = true;
};

/// The motion's waypoints and where a position k + t lies.
class Polyline {
 public:
  explicit Polyline(const std::vector<Eigen::VectorXd>& waypoints) : points_(waypoints) {
    if (points_.size() == 1) points_.push_back(points_.front());  // a still motion
  }
  int segments() const { return static_cast<int>(points_.size()) - 1; }
  Eigen::VectorXd step(int k) const { return points_[k + 1] - points_[k]; }
  /// The segment a position lies on, and how far along it.
  std::pair<int, double> locate(double s) const {
    const int k = std::clamp(static_cast<int>(std::floor(s)), 0, segments() - 1);
    return {k, s - k};
  }
  Eigen::VectorXd state(double s) const {
    const auto [k, t] = locate(s);
    return t <= 0.0 ? points_[k] : Eigen::VectorXd(points_[k] + t * (points_[k + 1] - points_[k]));
  }

 private:
  std::vector<Eigen::VectorXd> points_;
};

/// How far (as a motion position) a proof holds from `s` with `slack` to
/// use up: each segment takes its travel's share of it.
double holdsUntil(const Proof& proof, const Polyline& line, double s, double slack) {
  auto [k, t] = line.locate(s);
  for (; k < line.segments(); ++k, t = 0.0) {
    const double rest = (1.0 - t) * proof.travel[k];
    if (rest < slack || proof.travel[k] <= 0.0) {
      slack -= rest;
      continue;
    }
    return k + t + slack / proof.travel[k];
  }
  return line.segments();
}

/// What a proof's distance must stay above at position s: the requirement
/// never grows along the motion, so holding it from s on is conservative.
double required(const Proof& proof, const Polyline& line, double s, const CertifyOptions& options) {
  switch (proof.keeps) {
    case Keeps::kFree:
      return 0.0;
    case Keeps::kArriving: {
      const auto [k, t] = line.locate(s);
      const double toGo = (1.0 - t) * proof.travel[k] + proof.remaining[k + 1];
      return toGo >= options.approach_length ? options.clearance
                                             : options.clearance * toGo / options.approach_length;
    }
    case Keeps::kClearance:
      break;
  }
  return options.clearance;
}

/// The proofs of a motion under a rule: one per link with shapes against
/// the environment, one per link pair that may collide.
std::vector<Proof> proofsOf(const RobotModel& model, const MotionBound& bound, const Polyline& line,
                            CertifyRule rule) {
  std::vector<bool> fingertip(model.links().size(), false);
  for (const Fingertip& f : model.fingertips()) fingertip[static_cast<std::size_t>(f.link)] = true;
  const auto travels = [&](auto&& of) {
    std::vector<double> out(static_cast<std::size_t>(line.segments()));
    for (int k = 0; k < line.segments(); ++k) out[static_cast<std::size_t>(k)] = of(line.step(k));
    return out;
  };
  std::vector<int> links;
  for (std::size_t l = 0; l < model.links().size(); ++l)
    if (!model.links()[l].shapes.empty() || model.links()[l].mesh != nullptr)
      links.push_back(static_cast<int>(l));
  std::vector<Proof> proofs;
  for (const int link : links) {
    Proof p;
    p.link = link;
    p.travel = travels([&](const Eigen::VectorXd& step) { return bound.link(link, step); });
    const bool hand = model.isHandLink(link);
    // A link the motion does not move need only be free, as under the
    // clearance rule (CollisionScene); its distance is not the motion's.
    const bool still =
        std::all_of(p.travel.begin(), p.travel.end(), [](double travel) { return travel <= 0.0; });
    p.reported = !still;
    if (still || (rule == CertifyRule::kClosing && hand)) {
      p.keeps = Keeps::kFree;
    } else if (rule == CertifyRule::kApproach && hand) {
      p.keeps = Keeps::kArriving;
      p.remaining.assign(p.travel.size() + 1, 0.0);
      for (std::size_t k = p.travel.size(); k-- > 0;)
        p.remaining[k] = p.remaining[k + 1] + p.travel[k];
    }
    p.against = Against::kObstacles;
    proofs.push_back(p);
    // A fingertip closing on the target may touch it.
    if (rule == CertifyRule::kClosing && fingertip[static_cast<std::size_t>(link)]) continue;
    p.against = Against::kTarget;
    proofs.push_back(std::move(p));
  }
  for (std::size_t i = 0; i < links.size(); ++i)
    for (std::size_t j = i + 1; j < links.size(); ++j) {
      const int a = links[i], b = links[j];
      if (model.isCollisionDisabled(a, b)) continue;
      Proof p;
      p.link = a;
      p.other = b;
      p.against = Against::kLink;
      p.travel = travels([&](const Eigen::VectorXd& step) { return bound.pair(a, b, step); });
      const bool still = std::all_of(p.travel.begin(), p.travel.end(),
                                     [](double travel) { return travel <= 0.0; });
      const bool closingHand =
          rule == CertifyRule::kClosing && (model.isHandLink(a) || model.isHandLink(b));
      // As under the clearance rule (CollisionScene), two hand links need
      // only be free of each other (an open hand's fingers lie close), and
      // so do two links a few joints apart (a wrist's, close by the arm's
      // build).
      const bool builtClose = (model.isHandLink(a) && model.isHandLink(b)) ||
                              model.movingJointsBetween(a, b) <= kClearanceJointsApart;
      if (still || closingHand || builtClose) p.keeps = Keeps::kFree;
      p.reported = !still && !builtClose;
      proofs.push_back(std::move(p));
    }
  return proofs;
}

}  // namespace

MotionCertificate certifyPath(CollisionChecker& checker, const MotionBound& bound,
                              const std::vector<Eigen::VectorXd>& waypoints,
                              const CertifyOptions& options) {
  if (!std::isfinite(options.clearance) || options.clearance < 0.0)
    throw InvalidArgument("clearance", "must be a finite distance >= 0 (m), not " +
                                           std::to_string(options.clearance));
  if (!std::isfinite(options.approach_length) || !(options.approach_length > 0.0))
    throw InvalidArgument("approach_length", "must be a finite distance > 0 (m), not " +
                                                 std::to_string(options.approach_length));
  const RobotModel& model = checker.model();
  const int dofs = model.numDofs();
  if (waypoints.empty()) throw InvalidArgument("path", "has no waypoints");
  for (const Eigen::VectorXd& q : waypoints)
    if (q.size() != dofs || !q.allFinite())
      throw InvalidArgument(
          "path", "waypoints must be " + std::to_string(dofs) + " finite joint values each");
  const Polyline line(waypoints);
  std::vector<Proof> proofs = proofsOf(model, bound, line, options.rule);

  MotionCertificate certificate;
  certificate.clearance = std::numeric_limits<double>::infinity();
  std::vector<Proof*> due[3];
  std::vector<int> dueLinks;
  std::vector<std::pair<int, int>> duePairs;
  std::vector<double> distances[3];
  const double exactWithin = options.clearance + kExactBeyondClearance;
  while (true) {
    double s = line.segments();
    for (const Proof& proof : proofs) s = std::min(s, proof.until);
    if (s >= line.segments()) break;  // every proof reaches the end (or no shapes)
    if (certificate.queries >= options.max_queries || (options.stop && options.stop())) {
      certificate.exhausted = true;
      certificate.blocked_at = s;
      return certificate;
    }
    const Eigen::VectorXd q = line.state(s);
    for (auto& d : due) d.clear();
    for (Proof& proof : proofs)
      if (proof.until <= s) due[static_cast<int>(proof.against)].push_back(&proof);
    for (const Against against : {Against::kObstacles, Against::kTarget}) {
      const std::vector<Proof*>& these = due[static_cast<int>(against)];
      if (these.empty()) continue;
      dueLinks.clear();
      for (const Proof* p : these) dueLinks.push_back(p->link);
      checker.linkClearances(q, dueLinks, distances[static_cast<int>(against)],
                             against == Against::kObstacles ? CollisionRequest::obstaclesOnly()
                                                            : CollisionRequest::targetOnly(),
                             exactWithin);
    }
    duePairs.clear();
    for (const Proof* p : due[static_cast<int>(Against::kLink)])
      duePairs.emplace_back(p->link, p->other);
    checker.pairClearances(q, duePairs, distances[static_cast<int>(Against::kLink)]);
    certificate.self_queries += due[static_cast<int>(Against::kLink)].size();
    for (int kind = 0; kind < 3; ++kind) {
      certificate.queries += due[kind].size();
      for (std::size_t i = 0; i < due[kind].size(); ++i) {
        Proof& proof = *due[kind][i];
        const double distance = distances[kind][i];
        // Beyond exactWithin a distance may be a lower bound: not reported.
        const bool exact = proof.against == Against::kLink || distance < exactWithin;
        if (proof.reported && exact && distance < certificate.clearance) {
          certificate.clearance = distance;
          certificate.at = s;
          certificate.nearest_link = proof.link;
          certificate.nearest_other_link = proof.other;
          certificate.nearest_target = proof.against == Against::kTarget;
        }
        const double slack = distance - kDistanceTolerance - required(proof, line, s, options);
        if (slack <= kBlockingSlack) {
          certificate.blocked_at = s;
          return certificate;
        }
        proof.until = holdsUntil(proof, line, s, slack);
      }
    }
  }
  certificate.free = true;
  return certificate;
}

MotionCertificate certifySegment(CollisionChecker& checker, const MotionBound& bound,
                                 const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                                 const CertifyOptions& options) {
  const int dofs = checker.model().numDofs();
  if (a.size() != dofs || b.size() != dofs || !a.allFinite() || !b.allFinite())
    throw InvalidArgument("segment",
                          "ends must be " + std::to_string(dofs) + " finite joint values each");
  return certifyPath(checker, bound, {a, b}, options);
}

}  // namespace hfts::robot
