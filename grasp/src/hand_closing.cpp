#include "grasp/hand_closing.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <string>

#include "core/invalid_argument.h"
#include "robot/fingertip_geometry.h"
#include "robot/kinematics.h"
#include "robot/link_spheres.h"

namespace hfts::grasp {

const char* toString(FingerStop stop) {
  switch (stop) {
    case FingerStop::kPadContact:
      return "pad contact";
    case FingerStop::kOtherContact:
      return "touches with another part first";
    case FingerStop::kJointLimit:
      return "joint limit before contact";
    case FingerStop::kCoupled:
      return "stopped by the finger it is coupled to";
    case FingerStop::kStuck:
      return "closing did not settle";
    case FingerStop::kInside:
      return "inside the object before it closes";
  }
  return "unknown";
}

bool HandClosure::touches() const {
  return !fingers.empty() && std::all_of(fingers.begin(), fingers.end(), [](const auto& f) {
    return f.stop == FingerStop::kPadContact;
  });
}

GraspContacts HandClosure::contacts() const {
  GraspContacts out;
  out.positions.resize(3, static_cast<Eigen::Index>(fingers.size()));
  out.outward_normals.resize(3, static_cast<Eigen::Index>(fingers.size()));
  for (std::size_t f = 0; f < fingers.size(); ++f) {
    out.positions.col(static_cast<Eigen::Index>(f)) = fingers[f].contact;
    out.outward_normals.col(static_cast<Eigen::Index>(f)) = fingers[f].outward_normal;
  }
  return out;
}

std::string HandClosure::failure(const robot::RobotModel& model) const {
  std::string out;
  for (std::size_t f = 0; f < fingers.size(); ++f) {
    if (fingers[f].stop == FingerStop::kPadContact) continue;
    out += (out.empty() ? "" : "; ") + std::string("finger '") + model.fingertips()[f].name +
           "': " + toString(fingers[f].stop);
    if (fingers[f].stop == FingerStop::kOtherContact) out += " (" + fingers[f].link + ")";
  }
  return out;
}

/// A fingertip's finger: the links that move with it and, per link, how
/// fast its points can move.
struct HandCloser::Finger {
  int tip = 0;                   ///< index into RobotModel::fingertips()
  std::vector<int> links;        ///< links with shapes below the finger's first joint
  std::vector<int> chainJoints;  ///< joints from the palm to the fingertip link
  /// Per entry of `links`: (joint, lever) for each hand joint between the
  /// palm and the link: no point of the link is farther than `lever` from
  /// the joint's axis, whatever the joints in between do.
  std::vector<std::vector<std::pair<int, double>>> levers;
  /// How far from the fingertip point (m) the pad may touch a face it lies
  /// flat on: 1.5 pad radii (robot::padRadius), the pad's half-diagonal
  /// on the bundled hands.
  double patch_radius = 0.0;
};

/// Where a finger first touches, moving alone.
struct HandCloser::Touch {
  double t = 0.0;
  FingerStop stop = FingerStop::kJointLimit;
  int link = -1;
  robot::SurfacePoint surface;
};

namespace {

/// Joints from the palm down to `link` (empty when the link is not below
/// the palm).
std::vector<int> jointsBelowPalm(const robot::RobotModel& model, int link) {
  std::vector<int> path;
  while (link != model.palmLink()) {
    const int joint = model.links()[static_cast<std::size_t>(link)].parent_joint;
    if (joint < 0) return {};
    path.push_back(joint);
    link = model.joints()[static_cast<std::size_t>(joint)].parent_link;
  }
  std::reverse(path.begin(), path.end());
  return path;
}

/// Farthest point of a link's shapes from the link's frame origin.
double linkExtent(const robot::Link& link) {
  double extent = 0.0;
  for (const robot::CollisionShape& s : link.shapes) {
    double radius = s.size.x();  // sphere
    if (s.type == robot::CollisionShape::Type::kBox) radius = s.size.norm() / 2;
    if (s.type == robot::CollisionShape::Type::kCylinder)
      radius = std::hypot(s.size.x(), s.size.y() / 2);
    extent = std::max(extent, s.origin.translation().norm() + radius);
  }
  return extent;
}

/// How far a joint can move its child frame from its parent's origin.
double jointReach(const robot::RobotModel& model, const robot::Joint& j) {
  double reach = j.origin.translation().norm();
  if (j.type == robot::Joint::Type::kPrismatic && j.dof >= 0) {
    const auto d = static_cast<Eigen::Index>(j.dof);
    reach += std::max(std::abs(j.multiplier * model.lowerLimits()(d) + j.offset),
                      std::abs(j.multiplier * model.upperLimits()(d) + j.offset));
  }
  return reach;
}

}  // namespace

HandCloser::HandCloser(const robot::CollisionModel& collision, const robot::ObjectSurface& surface,
                       ClosingOptions options)
    : model_(collision.robot), spheres_(collision.spheres), surface_(surface), options_(options) {
  const robot::RobotModel& model = model_;
  if (!(options.contact_distance > 0.0) || !(options.pad_cone > 0.0) || options.max_steps < 1)
    throw InvalidArgument("options",
                          "contact_distance and pad_cone must be > 0 and max_steps >= 1");
  const auto& links = model.links();
  for (std::size_t f = 0; f < model.fingertips().size(); ++f) {
    Finger finger;
    finger.tip = static_cast<int>(f);
    finger.patch_radius = 1.5 * robot::padRadius(model, model.fingertips()[f]);
    finger.chainJoints = jointsBelowPalm(model, model.fingertips()[f].link);
    if (finger.chainJoints.empty()) continue;  // not below the palm: RobotModel forbids it
    for (std::size_t l = 0; l < links.size(); ++l) {
      const std::vector<int> path = jointsBelowPalm(model, static_cast<int>(l));
      if (links[l].shapes.empty() || path.empty() || path.front() != finger.chainJoints.front())
        continue;
      std::vector<std::pair<int, double>> levers;
      for (std::size_t i = 0; i < path.size(); ++i) {
        const robot::Joint& j = model.joints()[static_cast<std::size_t>(path[i])];
        if (j.dof < model.numArmDofs()) continue;  // fixed (dof -1) or an arm joint
        double lever = linkExtent(links[l]);
        for (std::size_t k = i + 1; k < path.size(); ++k)
          lever += jointReach(model, model.joints()[static_cast<std::size_t>(path[k])]);
        levers.emplace_back(path[i], lever);
      }
      finger.links.push_back(static_cast<int>(l));
      finger.levers.push_back(std::move(levers));
    }
    fingers_.push_back(std::move(finger));
  }
  // A parallel gripper: the only two fingertips share a hand DoF.
  const auto dofsOf = [&](const Finger& f) {
    std::vector<int> dofs;
    for (const int joint : f.chainJoints)
      if (model.joints()[static_cast<std::size_t>(joint)].dof >= model.numArmDofs())
        dofs.push_back(model.joints()[static_cast<std::size_t>(joint)].dof);
    std::sort(dofs.begin(), dofs.end());
    return dofs;
  };
  if (fingers_.size() == 2) {
    const std::vector<int> a = dofsOf(fingers_[0]), b = dofsOf(fingers_[1]);
    std::vector<int> shared;
    std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(shared));
    if (!shared.empty()) jaws_ = std::pair<std::size_t, std::size_t>{0, 1};
  }
}

HandCloser::~HandCloser() = default;

namespace {

/// Link poses of the hand alone at `hand`, in the object frame for a palm
/// at `palm` (object frame).
robot::LinkPoses handPoses(const robot::RobotModel& model, const Eigen::Isometry3d& palm,
                           const Eigen::VectorXd& hand) {
  Eigen::VectorXd q = model.home();
  q.tail(model.numHandDofs()) = hand;
  robot::LinkPoses poses = robot::forwardKinematics(model, q);
  const Eigen::Isometry3d toObject =
      palm * poses[static_cast<std::size_t>(model.palmLink())].inverse();
  for (Eigen::Isometry3d& pose : poses) pose = toObject * pose;
  return poses;
}

}  // namespace

std::vector<double> HandCloser::linkSpeeds(const Finger& finger,
                                           const Eigen::VectorXd& direction) const {
  // How fast a point of each link can move per unit of the closing
  // parameter: joint rates times levers.
  std::vector<double> speed(finger.links.size(), 0.0);
  for (std::size_t i = 0; i < finger.links.size(); ++i)
    for (const auto& [joint, lever] : finger.levers[i]) {
      const robot::Joint& j = model_.joints()[static_cast<std::size_t>(joint)];
      const double rate = std::abs(j.multiplier * direction(j.dof - model_.numArmDofs()));
      speed[i] += rate * (j.type == robot::Joint::Type::kRevolute ? lever : 1.0);
    }
  return speed;
}

HandCloser::Touch HandCloser::firstTouch(const Finger& finger, const Eigen::Isometry3d& palm,
                                         const Eigen::VectorXd& open,
                                         const Eigen::VectorXd& direction, double limit) const {
  const std::vector<double> speed = linkSpeeds(finger, direction);
  const auto posesAt = [&](double s) { return handPoses(model_, palm, open + s * direction); };
  const auto linkOf = [&](std::size_t i) -> const robot::Link& {
    return model_.links()[static_cast<std::size_t>(finger.links[i])];
  };
  // A point of link i (its first shape's centre): a clearance from the
  // distance grid names none.
  const auto pointOf = [&](std::size_t i, const Eigen::Isometry3d& pose) -> Eigen::Vector3d {
    return pose * linkOf(i).shapes.front().origin.translation();
  };
  std::vector<robot::Clearance> gap(finger.links.size());
  Touch out;
  double t = 0.0;
  for (int step = 0; step < options_.max_steps; ++step) {
    const robot::LinkPoses poses = posesAt(t);
    out.t = t;
    // Links apart may move by their distance (conservative advancement);
    // a link that touches stops the finger when it pushes into the
    // surface, and slides on when it only grazes it.
    double advance = std::numeric_limits<double>::infinity();
    std::vector<std::size_t> sliding;
    for (std::size_t i = 0; i < finger.links.size(); ++i) {
      const auto l = static_cast<std::size_t>(finger.links[i]);
      gap[i] = clearance(l, poses[l]);
      // Apart from the surface a link is outside or wholly inside: at the
      // start, tell which (later it cannot have passed through it). A link
      // crossing the surface at the start is inside when it is deeper than
      // a touch.
      if (step == 0 &&
          (gap[i].distance > 0.0 ? surface_.nearest(pointOf(i, poses[l])).signed_distance < 0.0
                                 : startsDeep(linkOf(i), poses[l]))) {
        out.stop = FingerStop::kInside;
        out.link = finger.links[i];
        return out;
      }
      if (gap[i].distance > options_.contact_distance) {
        // Aim at half the contact distance, so that no step ends touching
        // (where the nearest points are not defined).
        if (speed[i] > 0.0)
          advance = std::min(advance, (gap[i].distance - options_.contact_distance / 2) / speed[i]);
        continue;
      }
      // A link the closing does not move (its finger's DoF are still, at
      // the planned posture already) touches where it is: within the
      // contact distance it is a wall the other fingers push against.
      if (!(speed[i] > 0.0) || pushesIn(gap[i], poses[l], posesAt(t + kProbeStep)[l])) {
        stopAt(finger, i, poses, gap[i], out);
        return out;
      }
      sliding.push_back(i);
      if (speed[i] > 0.0) advance = std::min(advance, kSlideStep / speed[i]);
    }
    if (t >= limit) return out;     // kJointLimit
    if (!std::isfinite(advance)) {  // the finger does not move
      out.t = limit;
      return out;
    }
    const double next = std::min(limit, t + advance);
    // A grazing link must not sink into the surface as it slides on.
    const robot::LinkPoses ahead = posesAt(next);
    for (const std::size_t i : sliding) {
      const auto l = static_cast<std::size_t>(finger.links[i]);
      if (surface_.linkClearance(linkOf(i), ahead[l]).distance > 0.0) continue;
      if (surface_
              .linkDistance(linkOf(i), ahead[l], options_.contact_distance / 4,
                            -options_.contact_distance, -options_.contact_distance)
              .lower < -options_.contact_distance) {
        stopAt(finger, i, poses, gap[i], out);
        return out;
      }
    }
    t = next;
  }
  out.stop = FingerStop::kStuck;
  return out;
}

bool HandCloser::startsDeep(const robot::Link& link, const Eigen::Isometry3d& pose) const {
  return surface_
             .linkDistance(link, pose, options_.contact_distance / 4, -options_.contact_distance,
                           -options_.contact_distance)
             .lower < -options_.contact_distance;
}

robot::Clearance HandCloser::clearance(std::size_t link, const Eigen::Isometry3d& pose) const {
  // The link's spheres against the object's distance grid first: a few
  // look-ups where FCL's mesh distance costs a fraction of a millisecond.
  robot::Clearance far;
  far.distance = std::numeric_limits<double>::infinity();
  for (const robot::LinkSphere& s : spheres_.links[link].spheres)
    far.distance = std::min(far.distance, surface_.gridBound(pose * s.center) - s.radius);
  if (far.distance > kNear) return far;
  return surface_.linkClearance(model_.links()[link], pose);
}

bool HandCloser::pushesIn(const robot::Clearance& gap, const Eigen::Isometry3d& pose,
                          const Eigen::Isometry3d& later) const {
  if (!(gap.distance > 0.0)) return true;  // in touch: no direction to judge by
  const Eigen::Vector3d moved = later * (pose.inverse() * gap.on_link) - gap.on_link;
  const Eigen::Vector3d outward = surface_.nearest(gap.on_surface).normal;
  return moved.dot(outward) < -std::sin(kGrazeAngle) * moved.norm();
}

void HandCloser::stopAt(const Finger& finger, std::size_t i, const robot::LinkPoses& poses,
                        const robot::Clearance& gap, Touch& out) const {
  const int l = finger.links[i];
  const robot::Link& link = model_.links()[static_cast<std::size_t>(l)];
  const Eigen::Isometry3d& pose = poses[static_cast<std::size_t>(l)];
  // Apart by less than the contact distance, FCL names the nearest point;
  // in touch, the signed distance's search finds it.
  out.surface = gap.distance > 0.0
                    ? surface_.nearest(gap.on_surface)
                    : surface_.linkDistance(link, pose, options_.contact_distance / 4).surface;
  // The contact normal is the smooth side's: the mesh's inside a face, the
  // finger's where it touches an edge or a corner of the mesh. The line
  // between the two nearest points is both.
  constexpr double kSeparated = 1e-5;
  if (gap.distance > kSeparated) out.surface.normal = (gap.on_link - gap.on_surface).normalized();
  out.link = l;
  const robot::Fingertip& tip = model_.fingertips()[static_cast<std::size_t>(finger.tip)];
  const Eigen::Vector3d pad = pose.linear() * tip.normal;
  out.stop = l == tip.link && -out.surface.normal.dot(pad) >= std::cos(options_.pad_cone)
                 ? FingerStop::kPadContact
                 : FingerStop::kOtherContact;
  // A pad flat on a face touches along a patch, and FCL names any point of
  // it, one that can jump across the patch when the posture changes in its
  // 15th digit (and the grasp's epsilon with it). Where the fingertip's
  // own point is in the patch, that is the contact; else the patch's
  // centre.
  if (out.stop == FingerStop::kPadContact) {
    const robot::SurfacePoint atTip = surface_.nearest(pose * tip.point);
    if (std::abs(atTip.signed_distance) <= 2 * options_.contact_distance &&
        -atTip.normal.dot(pad) >= std::cos(options_.pad_cone))
      out.surface = atTip;
    else if (const std::optional<robot::SurfacePoint> centre = patchCentre(finger, link, pose, pad))
      out.surface = *centre;
  }
}

std::optional<robot::SurfacePoint> HandCloser::patchCentre(const Finger& finger,
                                                           const robot::Link& link,
                                                           const Eigen::Isometry3d& pose,
                                                           const Eigen::Vector3d& pad) const {
  // The surface points under a grid over the pad's disc (each within half
  // a grid step of the pad normal's line through its grid point) that
  // touch the link with the pad's side: their mean, put back on the
  // surface.
  constexpr int kHalf = 8;  // a 17 x 17 grid
  const robot::Fingertip& tip = model_.fingertips()[static_cast<std::size_t>(finger.tip)];
  const Eigen::Vector3d centre = pose * tip.point;
  const Eigen::Vector3d u = pad.unitOrthogonal(), v = pad.cross(u);
  const double step = finger.patch_radius / kHalf;
  const auto touches = [&](const robot::SurfacePoint& s) {
    return std::abs(robot::signedDistance(link, pose.inverse() * s.point)) <=
               2 * options_.contact_distance &&
           -s.normal.dot(pad) >= std::cos(options_.pad_cone);
  };
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int count = 0;
  for (int i = -kHalf; i <= kHalf; ++i)
    for (int j = -kHalf; j <= kHalf; ++j) {
      if (i * i + j * j > kHalf * kHalf) continue;
      const Eigen::Vector3d g = centre + step * (i * u + j * v);
      const robot::SurfacePoint s = surface_.nearest(g);
      const Eigen::Vector3d off = s.point - g;
      if ((off - off.dot(pad) * pad).norm() <= step / 2 && touches(s)) {
        sum += s.point;
        ++count;
      }
    }
  if (count == 0) return std::nullopt;
  const robot::SurfacePoint mean = surface_.nearest(sum / count);
  if (!touches(mean)) return std::nullopt;  // a patch that is not convex
  return mean;
}

HandClosure HandCloser::closeAt(const Eigen::Isometry3d& palm, const Eigen::VectorXd& open,
                                const Eigen::VectorXd& direction,
                                std::vector<Touch>& touches) const {
  const int arm = model_.numArmDofs();
  const Eigen::Index dofs = open.size();
  touches.assign(fingers_.size(), Touch{});
  // Which fingers each hand DoF moves, and each finger alone.
  std::vector<std::vector<std::size_t>> moved(static_cast<std::size_t>(dofs));
  for (std::size_t f = 0; f < fingers_.size(); ++f) {
    double limit = std::numeric_limits<double>::infinity();
    for (const int joint : fingers_[f].chainJoints) {
      const int dof = model_.joints()[static_cast<std::size_t>(joint)].dof - arm;
      if (dof < 0 || direction(dof) == 0.0) continue;
      moved[static_cast<std::size_t>(dof)].push_back(f);
      const double bound =
          direction(dof) > 0.0 ? model_.upperLimits()(arm + dof) : model_.lowerLimits()(arm + dof);
      limit = std::min(limit, std::max(0.0, (bound - open(dof)) / direction(dof)));
    }
    if (!std::isfinite(limit)) limit = 0.0;  // nothing moves this finger
    touches[f] = firstTouch(fingers_[f], palm, open, direction, limit);
  }
  // Fingers on one DoF stop together, at the first touch among them.
  std::vector<double> stopAt(fingers_.size());
  for (std::size_t f = 0; f < fingers_.size(); ++f) stopAt[f] = touches[f].t;
  for (const std::vector<std::size_t>& group : moved)
    for (const std::size_t f : group)
      for (const std::size_t g : group) stopAt[f] = std::min(stopAt[f], touches[g].t);
  HandClosure out;
  out.palm = palm;
  out.hand = open;
  for (Eigen::Index d = 0; d < dofs; ++d) {
    const auto& group = moved[static_cast<std::size_t>(d)];
    if (group.empty()) continue;
    out.hand(d) = open(d) + stopAt[group.front()] * direction(d);
  }
  for (std::size_t f = 0; f < fingers_.size(); ++f) {
    FingerClosure c;
    const Touch& touch = touches[f];
    // Stopped before its own touch: still touching when it had no further
    // to go than the contact distance (jaws centred on the object).
    const std::vector<double> speed = linkSpeeds(fingers_[f], direction);
    const double reach = (touch.t - stopAt[f]) * *std::max_element(speed.begin(), speed.end());
    c.stop = reach > options_.contact_distance ? FingerStop::kCoupled : touch.stop;
    c.travel = stopAt[f];
    if (touch.link >= 0 && c.stop != FingerStop::kCoupled) {
      c.link = model_.links()[static_cast<std::size_t>(touch.link)].name;
      c.contact = touch.surface.point;
      c.outward_normal = touch.surface.normal;
    }
    out.fingers.push_back(std::move(c));
  }
  return out;
}

Eigen::Isometry3d HandCloser::squared(const HandClosure& closure, const std::vector<Touch>& touches,
                                      const Eigen::VectorXd& open) const {
  // A parallel gripper closing on two nearly opposite faces turns the
  // object (or its pads give) until the jaws lie flat on them; a rigid jaw
  // a few degrees off touches with its edge instead, centimetres from its
  // pad. The planner turns the palm about the point between the fingertips
  // so that the first jaw's pad normal points along the faces' common
  // normal.
  constexpr double kFlat = 0.9063;       // faces within 25 degrees of opposite
  constexpr double kSquare = 0.0017453;  // 0.1 degree: square enough
  if (!jaws_) return closure.palm;
  const auto [first, second] = *jaws_;
  if (touches[first].link < 0 || touches[second].link < 0) return closure.palm;
  // The faces under the pads' own points: a tilted jaw may touch an edge
  // first, whose normal says nothing of the face it should lie on.
  const robot::LinkPoses poses = handPoses(model_, closure.palm, open);
  const robot::Fingertip& tipA = model_.fingertips()[first];
  const robot::Fingertip& tipB = model_.fingertips()[second];
  const Eigen::Vector3d na =
      surface_.nearest(poses[static_cast<std::size_t>(tipA.link)] * tipA.point).normal;
  const Eigen::Vector3d nb =
      surface_.nearest(poses[static_cast<std::size_t>(tipB.link)] * tipB.point).normal;
  if (na.dot(nb) > -kFlat) return closure.palm;
  const Eigen::Vector3d pad = poses[static_cast<std::size_t>(tipA.link)].linear() * tipA.normal;
  const Eigen::Vector3d along = (nb - na).normalized();
  const double angle = std::acos(std::clamp(pad.dot(along), -1.0, 1.0));
  if (angle < kSquare || angle > std::acos(kFlat)) return closure.palm;
  const Eigen::Vector3d pivot = (poses[static_cast<std::size_t>(tipA.link)] * tipA.point +
                                 poses[static_cast<std::size_t>(tipB.link)] * tipB.point) /
                                2;
  return Eigen::Translation3d(pivot) * Eigen::Quaterniond::FromTwoVectors(pad, along) *
         Eigen::Translation3d(-pivot) * closure.palm;
}

Eigen::Isometry3d HandCloser::centred(const HandClosure& closure, const std::vector<Touch>& touches,
                                      const Eigen::VectorXd& open,
                                      const Eigen::VectorXd& direction) const {
  // Two fingertips on one DoF that move against each other (a parallel
  // gripper's jaws), both of which would touch: shift the palm along their
  // line so that they reach the surface at the same travel.
  constexpr double kOpposed = 0.9;  // cos 25 degrees
  if (!jaws_) return closure.palm;
  const auto [first, second] = *jaws_;
  const Touch& a = touches[first];
  const Touch& b = touches[second];
  if (a.link < 0 || b.link < 0) return closure.palm;
  // Fingertip velocities per unit travel, at each one's touch.
  const auto velocity = [&](std::size_t f, double t) {
    constexpr double kStep = 1e-4;
    const robot::Fingertip& tip = model_.fingertips()[f];
    const auto at = [&](double s) {
      return handPoses(model_, closure.palm,
                       open + s * direction)[static_cast<std::size_t>(tip.link)] *
             tip.point;
    };
    return Eigen::Vector3d((at(t + kStep) - at(t)) / kStep);
  };
  const Eigen::Vector3d va = velocity(first, a.t), vb = velocity(second, b.t);
  const double sa = va.norm(), sb = vb.norm();
  if (sa <= 0.0 || sb <= 0.0 || va.dot(vb) > -kOpposed * sa * sb) return closure.palm;
  const double shift = (b.t - a.t) / (1.0 / sa + 1.0 / sb);
  if (std::abs(shift) <= options_.contact_distance / 2) return closure.palm;
  // Away from the jaw that touches first: it then travels `shift` more.
  return Eigen::Translation3d(-shift * va / sa) * closure.palm;
}

HandClosure HandCloser::close(const Eigen::Isometry3d& palm, const Eigen::VectorXd& open,
                              const Eigen::VectorXd& target) const {
  const Eigen::Index dofs = model_.numHandDofs();
  if (open.size() != dofs || target.size() != dofs || !open.allFinite() || !target.allFinite() ||
      !palm.matrix().allFinite())
    throw InvalidArgument("hand", "needs a finite palm pose and two postures of " +
                                      std::to_string(dofs) + " finite values");
  const Eigen::VectorXd direction = target - open;
  std::vector<Touch> touches;
  HandClosure closure = closeAt(palm, open, direction, touches);
  for (int round = 0; round < options_.centering_rounds; ++round) {
    Eigen::Isometry3d moved = squared(closure, touches, open);
    if (moved.matrix() == closure.palm.matrix()) moved = centred(closure, touches, open, direction);
    if (moved.matrix() == closure.palm.matrix()) break;
    closure = closeAt(moved, open, direction, touches);
  }
  return closure;
}

}  // namespace hfts::grasp
