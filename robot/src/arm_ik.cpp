// Arm inverse kinematics: closed forms for a spherical wrist on a planar
// shoulder-elbow chain and for three parallel middle axes (UR type), the
// geometry read from the model; damped least squares otherwise. Both
// closed forms work on the axes as they are at the zero configuration
// (product of exponentials) with the Paden-Kahan subproblems.
#include "robot/arm_ik.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "robot/kinematics.h"

namespace hfts::robot {
namespace {

constexpr double kGeometryTolerance = 1e-9;
/// Numerical solutions of a redundant arm closer than this (rad, every
/// joint) count as the same.
constexpr double kDistinctRedundantSolutions = 0.1;

using Vec2 = Eigen::Vector2d;

double angleOf(const Vec2& v) {
  return std::atan2(v.y(), v.x());
}
Vec2 rotated(const Vec2& v, double angle) {
  return Eigen::Rotation2Dd(angle) * v;
}

Eigen::Matrix3d rotation(const Eigen::Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis).toRotationMatrix();
}

/// Paden-Kahan subproblem 1: the angle that rotates p onto q about axis w.
double subproblem1(const Eigen::Vector3d& w, const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
  const Eigen::Vector3d pp = p - w * w.dot(p), qq = q - w * w.dot(q);
  return std::atan2(w.dot(pp.cross(qq)), pp.dot(qq));
}

/// Paden-Kahan subproblem 2: angles (t1, t2) with R(w1,t1) R(w2,t2) p = q,
/// for intersecting, non-parallel axes through the origin. Up to two.
std::vector<std::pair<double, double>> subproblem2(const Eigen::Vector3d& w1,
                                                   const Eigen::Vector3d& w2,
                                                   const Eigen::Vector3d& p,
                                                   const Eigen::Vector3d& q) {
  const double c = w1.dot(w2);
  const double denominator = c * c - 1.0;
  const double alpha = (c * w2.dot(p) - w1.dot(q)) / denominator;
  const double beta = (c * w1.dot(q) - w2.dot(p)) / denominator;
  const Eigen::Vector3d cross = w1.cross(w2);
  const double gamma2 =
      (p.squaredNorm() - alpha * alpha - beta * beta - 2 * alpha * beta * c) / cross.squaredNorm();
  if (gamma2 < -1e-12) return {};
  const double gamma = std::sqrt(std::max(0.0, gamma2));
  std::vector<std::pair<double, double>> out;
  for (const double sign : {1.0, -1.0}) {
    const Eigen::Vector3d z = alpha * w1 + beta * w2 + sign * gamma * cross;
    out.emplace_back(subproblem1(w1, z, q), subproblem1(w2, p, z));
    if (gamma == 0.0) break;
  }
  return out;
}

double wrapToPi(double a) {
  return std::remainder(a, 2.0 * M_PI);
}

}  // namespace

struct ArmIk::Impl {
  RobotModel model;
  IkOptions options;
  std::vector<int> armJoints;  // joint index of arm DoF 0..5
  Eigen::Isometry3d palmInFlange = Eigen::Isometry3d::Identity();
  // Product of exponentials of the arm: axes and points at the zero
  // configuration, and the flange pose there. Much cheaper than full FK.
  std::vector<Eigen::Vector3d> axis, point;
  Eigen::Isometry3d flange0 = Eigen::Isometry3d::Identity();
  Eigen::Matrix3d frame4Zero = Eigen::Matrix3d::Identity();

  // Closed-form geometry (valid when form is not kNumerical).
  ArmIk::Form form = ArmIk::Form::kNumerical;
  Eigen::Vector3d o1, eh, er;  // axis-1 point, axis-1 direction, radial direction
  Vec2 o2, upper, fore;        // shoulder point and link vectors in the (r, h) plane
  double s2 = 1, s3 = 1;       // axes 2, 3 along +/- (eh x er)
  Eigen::Vector3d wristInFlange, wrist0;
  Eigen::Vector3d w4, w5, w6;  // wrist axes in the joint-4 frame at zero
  Eigen::Matrix3d flangeInWrist0;
  // Three parallel axes (UR type): their direction ep, the point where axes 5
  // and 6 meet (zero configuration, and in the flange frame), its offset
  // along the direction from the axis-1 point, and a point on axis 4.
  Eigen::Vector3d ep, ea, eb, meet0, meetInFlange, onAxis4;
  double meetOffset = 0.0;
  double sy[3] = {1, 1, 1};  // axes 2-4 along +/- ep

  explicit Impl(const RobotModel& m) : model(m) {}

  int dofs() const { return model.numArmDofs(); }

  Eigen::Isometry3d jointFrame(const LinkPoses& poses, int d) const {
    const Joint& j =
        model.joints()[static_cast<std::size_t>(armJoints[static_cast<std::size_t>(d)])];
    return poses[static_cast<std::size_t>(j.parent_link)] * j.origin;
  }

  Eigen::Vector3d jointAxis(const LinkPoses& poses, int d) const {
    const Joint& j =
        model.joints()[static_cast<std::size_t>(armJoints[static_cast<std::size_t>(d)])];
    return jointFrame(poses, d).linear() * j.axis;
  }

  void findChain();
  void detectClosedForm();
  void detectSphericalWrist();
  void detectThreeParallel();
  std::vector<Eigen::VectorXd> closedForm(const Eigen::Isometry3d& flange) const;
  std::vector<Eigen::VectorXd> threeParallel(const Eigen::Isometry3d& flange) const;
  void appendThreeParallelArm(const Eigen::Isometry3d& flange, double q1, double q5,
                              std::vector<Eigen::VectorXd>& out) const;
  void appendWristSolutions(const Eigen::Vector3d& q123, const Eigen::Matrix3d& target,
                            std::vector<Eigen::VectorXd>& out) const;
  void appendTurns(const Eigen::VectorXd& base, std::vector<Eigen::VectorXd>& out) const;
  std::optional<Eigen::VectorXd> descend(const Eigen::Isometry3d& flange,
                                         Eigen::VectorXd arm) const;
  bool reaches(const Eigen::VectorXd& arm, const Eigen::Isometry3d& flange) const;
  Vec2 planar(const Eigen::Vector3d& p) const { return Vec2(p.dot(ea), p.dot(eb)); }
  Eigen::Isometry3d flangePose(const Eigen::VectorXd& arm) const {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    for (int d = 0; d < dofs(); ++d) t = t * screw(d, arm(d));
    return t * flange0;
  }
  /// Where joints 1-3 put the wrist centre (PoE on its zero position).
  Eigen::Vector3d wristCentre(const Eigen::Vector3d& q123) const {
    return screw(0, q123(0)) * (screw(1, q123(1)) * (screw(2, q123(2)) * wrist0));
  }
  /// exp(xi_d q): rotation about the zero-configuration axis through its point.
  Eigen::Isometry3d screw(int d, double q) const {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = rotation(axis[d], q);
    t.translation() = point[d] - t.linear() * point[d];
    return t;
  }
};

void ArmIk::Impl::findChain() {
  const int n = dofs();
  if (n < 6)
    throw ModelError("ArmIk: the arm must have at least 6 DoF (a full pose needs 6), it has " +
                     std::to_string(n));
  armJoints.assign(static_cast<std::size_t>(n), -1);
  for (std::size_t j = 0; j < model.joints().size(); ++j) {
    const Joint& joint = model.joints()[j];
    if (joint.dof >= 0 && joint.dof < n) {
      if (joint.type != Joint::Type::kRevolute || joint.multiplier != 1.0 || joint.offset != 0.0)
        throw ModelError("ArmIk: arm joint '" + joint.name + "' must be a plain revolute joint");
      armJoints[static_cast<std::size_t>(joint.dof)] = static_cast<int>(j);
    }
  }
  // Walking from the flange to the root must meet the arm joints n..1 in order.
  int expected = n - 1;
  for (int l = model.flangeLink(); model.links()[static_cast<std::size_t>(l)].parent_joint >= 0;) {
    const int j = model.links()[static_cast<std::size_t>(l)].parent_joint;
    const Joint& joint = model.joints()[static_cast<std::size_t>(j)];
    if (joint.type != Joint::Type::kFixed) {
      if (expected < 0 || armJoints[static_cast<std::size_t>(expected)] != j)
        throw ModelError("ArmIk: the arm joints are not a chain from the base to the flange");
      --expected;
    }
    l = joint.parent_link;
  }
  if (expected != -1) throw ModelError("ArmIk: not every arm joint lies between base and flange");
  for (int l = model.palmLink(); l != model.flangeLink();) {
    const int j = model.links()[static_cast<std::size_t>(l)].parent_joint;
    if (j < 0 || model.joints()[static_cast<std::size_t>(j)].type != Joint::Type::kFixed)
      throw ModelError("ArmIk: the palm must be rigidly fixed below the flange");
    l = model.joints()[static_cast<std::size_t>(j)].parent_link;
  }
  const LinkPoses zero = forwardKinematics(model, Eigen::VectorXd::Zero(model.numDofs()));
  palmInFlange = zero[static_cast<std::size_t>(model.flangeLink())].inverse() *
                 zero[static_cast<std::size_t>(model.palmLink())];
  for (int d = 0; d < n; ++d) {
    axis.push_back(jointAxis(zero, d));
    point.push_back(jointFrame(zero, d).translation());
  }
  flange0 = zero[static_cast<std::size_t>(model.flangeLink())];
  frame4Zero = jointFrame(zero, 3).linear();
}

void ArmIk::Impl::detectClosedForm() {
  if (dofs() != 6) return;  // redundant arms: numerical
  detectSphericalWrist();
  if (form == ArmIk::Form::kNumerical) detectThreeParallel();
}

void ArmIk::Impl::detectSphericalWrist() {
  const LinkPoses zero = forwardKinematics(model, Eigen::VectorXd::Zero(model.numDofs()));
  Eigen::Vector3d o[6], u[6];
  for (int d = 0; d < 6; ++d) {
    o[d] = jointFrame(zero, d).translation();
    u[d] = jointAxis(zero, d);
  }
  const double tol = kGeometryTolerance;
  // Wrist centre: where axes 4 and 5 meet; axis 6 must pass through it.
  const Eigen::Vector3d n45 = u[3].cross(u[4]);
  if (n45.norm() < 1e-6 || std::abs(n45.normalized().dot(o[4] - o[3])) > tol) return;
  const double t = (o[4] - o[3]).cross(u[4]).dot(n45) / n45.squaredNorm();
  const Eigen::Vector3d wrist = o[3] + t * u[3];
  if ((wrist - o[5]).cross(u[5]).norm() > tol || u[4].cross(u[5]).norm() < 1e-6) return;
  // Planar shoulder and elbow: axis 1 perpendicular to the parallel axes 2, 3,
  // and no lateral offset of shoulder, elbow or wrist.
  o1 = o[0];
  eh = u[0];
  const Eigen::Vector3d v = wrist - o1, radial = v - eh * eh.dot(v);
  if (radial.norm() < 1e-6) return;
  er = radial.normalized();
  const Eigen::Vector3d ey = eh.cross(er);
  if (u[1].cross(ey).norm() > tol || u[2].cross(ey).norm() > tol) return;
  for (const Eigen::Vector3d& p : {o[1], o[2], wrist})
    if (std::abs((p - o1).dot(ey)) > tol) return;
  auto planar = [&](const Eigen::Vector3d& p) { return Vec2((p - o1).dot(er), (p - o1).dot(eh)); };
  o2 = planar(o[1]);
  upper = planar(o[2]) - o2;
  fore = planar(wrist) - planar(o[2]);
  s2 = u[1].dot(ey) > 0 ? 1.0 : -1.0;
  s3 = u[2].dot(ey) > 0 ? 1.0 : -1.0;
  wristInFlange = flange0.inverse() * wrist;
  wrist0 = wrist;
  const Eigen::Matrix3d frame4 = jointFrame(zero, 3).linear();
  w4 = frame4.transpose() * u[3];
  w5 = frame4.transpose() * u[4];
  w6 = frame4.transpose() * u[5];
  flangeInWrist0 = frame4.transpose() * flange0.linear();
  form = ArmIk::Form::kSphericalWrist;
}

void ArmIk::Impl::detectThreeParallel() {
  const double tol = kGeometryTolerance;
  // Axes 2, 3 and 4 parallel; axes 1 and 5 perpendicular to them.
  ep = axis[1];
  for (const int d : {2, 3})
    if (axis[d].cross(ep).norm() > tol) return;
  if (std::abs(axis[0].dot(ep)) > tol || std::abs(axis[4].dot(ep)) > tol) return;
  // Axes 5 and 6 meet in one point.
  const Eigen::Vector3d n56 = axis[4].cross(axis[5]);
  if (n56.norm() < 1e-6 || std::abs(n56.normalized().dot(point[5] - point[4])) > tol) return;
  meet0 = point[4] + (point[5] - point[4]).cross(axis[5]).dot(n56) / n56.squaredNorm() * axis[4];
  meetInFlange = flange0.inverse() * meet0;
  meetOffset = (meet0 - point[0]).dot(ep);
  onAxis4 = point[3];
  for (int i = 0; i < 3; ++i)
    sy[i] = axis[static_cast<std::size_t>(i) + 1].dot(ep) > 0 ? 1.0 : -1.0;
  // The plane of the shoulder and the elbow, (ea, eb, ep) right-handed: a
  // rotation by t about +ep turns its coordinates by +t.
  ea = ep.unitOrthogonal();
  eb = ep.cross(ea);
  o2 = planar(point[1]);
  upper = planar(point[2]) - o2;
  fore = planar(onAxis4) - planar(point[2]);
  if (upper.norm() < 1e-6 || fore.norm() < 1e-6) return;
  form = ArmIk::Form::kThreeParallel;
}

std::vector<Eigen::VectorXd> ArmIk::Impl::closedForm(const Eigen::Isometry3d& flange) const {
  std::vector<Eigen::VectorXd> out;
  const Eigen::Vector3d v = flange * wristInFlange - o1;
  const Eigen::Vector3d radial = v - eh * eh.dot(v);
  const Eigen::Vector3d ey = eh.cross(er);
  // Axis 1 turns the arm plane about eh: e_r(q1) = cos q1 er + sin q1 (eh x er).
  const double front = radial.norm() < 1e-12 ? 0.0 : std::atan2(radial.dot(ey), radial.dot(er));
  for (const int side : {1, -1}) {
    const double q1 = wrapToPi(side > 0 ? front : front + M_PI);
    const Vec2 target(side * radial.norm(), v.dot(eh));
    // Elbow: |target - o2|^2 = |A|^2 + |B|^2 + 2|A||B| cos(delta + phi3).
    const Vec2 d = target - o2;
    const double a = upper.norm(), b = fore.norm();
    const double c = (d.squaredNorm() - a * a - b * b) / (2 * a * b);
    if (std::abs(c) > 1.0 + 1e-12) continue;
    const double delta = angleOf(fore) - angleOf(upper);
    for (const int elbow : {1, -1}) {
      const double phi3 = elbow * std::acos(std::clamp(c, -1.0, 1.0)) - delta;
      const double phi2 = angleOf(d) - angleOf(upper + rotated(fore, phi3));
      // A rotation by q about +ey turns the (r, h) plane by -q.
      const Eigen::Vector3d q123(q1, -s2 * phi2, -s3 * phi3);
      if ((wristCentre(q123) - (o1 + v)).norm() <= options.tolerance)
        appendWristSolutions(q123, flange.linear(), out);
      if (c >= 1.0 || c <= -1.0) break;
    }
  }
  return out;
}

// Three parallel axes (UR type). Axes 5 and 6 meet in a point that only
// joints 1-4 move, and its offset along the parallel axes from axis 1 is
// fixed: that gives q1 (two). The angle between axis 6 and the parallel
// axes is set by q5 alone (two). The orientation then gives the sum of
// q2..q4 and q6, and the point on axis 4 below the meeting point the planar
// shoulder and elbow (two). Up to eight solutions, each verified by
// forward kinematics.
std::vector<Eigen::VectorXd> ArmIk::Impl::threeParallel(const Eigen::Isometry3d& flange) const {
  std::vector<Eigen::VectorXd> out;
  const Eigen::Vector3d v = flange * meetInFlange - point[0];
  // Axis 1 turns ep to cos(q1) ep + sin(q1) (axis1 x ep).
  const double along = v.dot(ep), side = v.dot(axis[0].cross(ep)), r = std::hypot(along, side);
  if (r < 1e-12 || std::abs(meetOffset) > r) return out;
  const double front = std::atan2(side, along), spread = std::acos(meetOffset / r);
  const Eigen::Vector3d axis6 = flange.linear() * flange0.linear().transpose() * axis[5];
  // ep . R(axis5, q5) axis6_0 = c5 cos(q5) + s5 sin(q5), as axis 5 is
  // perpendicular to ep.
  const double c5 = ep.dot(axis[5]), s5 = ep.dot(axis[4].cross(axis[5])), r5 = std::hypot(c5, s5);
  for (const double q1 : {front + spread, front - spread}) {
    const double wanted = (rotation(axis[0], q1) * ep).dot(axis6);
    if (std::abs(wanted) > r5 + 1e-12) continue;
    const double tilt = std::acos(std::clamp(wanted / r5, -1.0, 1.0)), q5Front = std::atan2(s5, c5);
    for (const double q5 : {q5Front + tilt, q5Front - tilt}) {
      appendThreeParallelArm(flange, q1, q5, out);
      if (tilt == 0.0) break;
    }
    if (spread == 0.0) break;
  }
  return out;
}

void ArmIk::Impl::appendThreeParallelArm(const Eigen::Isometry3d& flange, double q1, double q5,
                                         std::vector<Eigen::VectorXd>& out) const {
  const Eigen::Matrix3d r1 = rotation(axis[0], q1), r5 = rotation(axis[4], q5);
  const Eigen::Matrix3d target = flange.linear(), zero = flange0.linear();
  // target = r1 R(ep, phi) r5 R(axis6, q6) zero, phi = sum of s_i q_i (i = 2..4).
  const Eigen::Vector3d tilted = r5 * axis[5];
  double phi = 0.0, q6 = 0.0;
  if ((tilted - ep * ep.dot(tilted)).norm() > 1e-9) {
    phi = subproblem1(ep, tilted, r1.transpose() * target * zero.transpose() * axis[5]);
    const Eigen::Matrix3d turn6 =
        (r1 * rotation(ep, phi) * r5).transpose() * target * zero.transpose();
    const Eigen::Vector3d probe = axis[5].unitOrthogonal();
    q6 = subproblem1(axis[5], probe, turn6 * probe);
  } else {  // axis 6 along ep: only phi + q6 matters; take q6 = 0
    const Eigen::Matrix3d turnY = r1.transpose() * target * zero.transpose() * r5.transpose();
    const Eigen::Vector3d probe = ep.unitOrthogonal();
    phi = subproblem1(ep, probe, turnY * probe);
  }
  // The point on axis 4 that joints 2 and 3 must place.
  const Eigen::Vector3d meet = screw(0, -q1) * (flange * meetInFlange);
  const Vec2 d = planar(meet - rotation(ep, phi) * (meet0 - onAxis4)) - o2;
  const double a = upper.norm(), b = fore.norm();
  const double c = (d.squaredNorm() - a * a - b * b) / (2 * a * b);
  if (std::abs(c) > 1.0 + 1e-12) return;
  const double delta = angleOf(fore) - angleOf(upper);
  for (const int elbow : {1, -1}) {
    const double phi3 = elbow * std::acos(std::clamp(c, -1.0, 1.0)) - delta;
    const double phi2 = angleOf(d) - angleOf(upper + rotated(fore, phi3));
    Eigen::VectorXd arm(6);
    arm << q1, sy[0] * phi2, sy[1] * phi3, sy[2] * (phi - phi2 - phi3), q5, q6;
    for (int j = 0; j < 6; ++j) arm(j) = wrapToPi(arm(j));
    if (reaches(arm, flange)) out.push_back(arm);
    if (c >= 1.0 || c <= -1.0) break;
  }
}

void ArmIk::Impl::appendWristSolutions(const Eigen::Vector3d& q123, const Eigen::Matrix3d& target,
                                       std::vector<Eigen::VectorXd>& out) const {
  Eigen::VectorXd arm = Eigen::VectorXd::Zero(6);
  arm.head<3>() = q123;
  // The joint-4 frame turns with the first three rotations (PoE).
  const Eigen::Matrix3d frame4 = rotation(axis[0], q123(0)) * rotation(axis[1], q123(1)) *
                                 rotation(axis[2], q123(2)) * frame4Zero;
  const Eigen::Matrix3d m = frame4.transpose() * target * flangeInWrist0.transpose();
  const Eigen::Vector3d probe = w6.unitOrthogonal();
  for (const auto& [q4, q5] : subproblem2(w4, w5, w6, m * w6)) {
    const Eigen::Matrix3d r45 = rotation(w4, q4) * rotation(w5, q5);
    const double q6 = subproblem1(w6, probe, r45.transpose() * m * probe);
    // Verify: the wrist orientation must reproduce m (the position was
    // checked with the wrist centre by the caller).
    const double error = (r45 * rotation(w6, q6) - m).cwiseAbs().maxCoeff();
    if (error > options.tolerance) continue;
    arm.tail<3>() << q4, q5, q6;
    out.push_back(arm);
  }
}

/// Adds every variant of `base` whose angles differ by whole turns and lie
/// within the limits.
void ArmIk::Impl::appendTurns(const Eigen::VectorXd& base,
                              std::vector<Eigen::VectorXd>& out) const {
  const int n = dofs();
  std::vector<std::vector<double>> turns(static_cast<std::size_t>(n));
  for (int d = 0; d < n; ++d) {
    const double wrapped = wrapToPi(base(d));
    for (int k = -2; k <= 2; ++k) {
      const double value = wrapped + 2.0 * M_PI * k;
      if (value >= model.lowerLimits()(d) - 1e-12 && value <= model.upperLimits()(d) + 1e-12)
        turns[static_cast<std::size_t>(d)].push_back(
            std::clamp(value, model.lowerLimits()(d), model.upperLimits()(d)));
    }
    if (turns[static_cast<std::size_t>(d)].empty()) return;
  }
  std::vector<std::size_t> pick(static_cast<std::size_t>(n), 0);
  while (true) {
    Eigen::VectorXd arm(n);
    for (int d = 0; d < n; ++d)
      arm(d) = turns[static_cast<std::size_t>(d)][pick[static_cast<std::size_t>(d)]];
    out.push_back(arm);
    int d = 0;
    while (d < n &&
           ++pick[static_cast<std::size_t>(d)] == turns[static_cast<std::size_t>(d)].size())
      pick[static_cast<std::size_t>(d++)] = 0;
    if (d == n) break;
  }
}

bool ArmIk::Impl::reaches(const Eigen::VectorXd& arm, const Eigen::Isometry3d& flange) const {
  const Eigen::Isometry3d reached = flangePose(arm);
  const double position = (reached.translation() - flange.translation()).norm();
  const double angle = Eigen::AngleAxisd(reached.linear().transpose() * flange.linear()).angle();
  return position <= std::max(options.tolerance, 1e-9) &&
         std::abs(angle) <= std::max(options.tolerance, 1e-9);
}

std::optional<Eigen::VectorXd> ArmIk::Impl::descend(const Eigen::Isometry3d& flange,
                                                    Eigen::VectorXd arm) const {
  const double lambda2 = options.damping * options.damping;
  const int n = dofs();
  Eigen::Matrix<double, 6, Eigen::Dynamic> j(6, n);
  Eigen::Matrix3Xd axes(3, n), points(3, n);
  for (int it = 0; it < options.iterations; ++it) {
    // The flange pose and its Jacobian in one pass over the product of
    // exponentials: each joint's axis and point as the joints before it
    // carry them (no full forward kinematics of every link).
    Eigen::Isometry3d prefix = Eigen::Isometry3d::Identity();
    for (int d = 0; d < n; ++d) {
      axes.col(d) = prefix.linear() * axis[static_cast<std::size_t>(d)];
      points.col(d) = prefix * point[static_cast<std::size_t>(d)];
      prefix = prefix * screw(d, arm(d));
    }
    const Eigen::Isometry3d at = prefix * flange0;
    Eigen::Matrix<double, 6, 1> error;
    error.head<3>() = flange.translation() - at.translation();
    const Eigen::AngleAxisd rot(flange.linear() * at.linear().transpose());
    error.tail<3>() = rot.angle() * rot.axis();
    if (error.norm() < 1e-12) break;
    for (int d = 0; d < n; ++d) {
      j.col(d).head<3>() = axes.col(d).cross(at.translation() - points.col(d));
      j.col(d).tail<3>() = axes.col(d);
    }
    // Less damping near the goal gives quadratic convergence at the end.
    const double damping = error.norm() < 1e-3 ? 1e-9 : lambda2;
    const Eigen::VectorXd step =
        j.transpose() *
        (j * j.transpose() + damping * Eigen::Matrix<double, 6, 6>::Identity()).ldlt().solve(error);
    arm = (arm + step)
              .cwiseMax(model.lowerLimits().head(dofs()))
              .cwiseMin(model.upperLimits().head(dofs()));
  }
  if (!reaches(arm, flange)) return std::nullopt;
  return arm;
}

ArmIk::ArmIk(const RobotModel& model) : impl_(std::make_unique<Impl>(model)) {
  impl_->findChain();
  impl_->detectClosedForm();
}

ArmIk::~ArmIk() = default;
ArmIk::ArmIk(ArmIk&&) noexcept = default;

bool ArmIk::isAnalytic() const {
  return impl_->form != Form::kNumerical;
}
ArmIk::Form ArmIk::form() const {
  return impl_->form;
}
IkOptions& ArmIk::options() {
  return impl_->options;
}
const Eigen::Isometry3d& ArmIk::palmInFlange() const {
  return impl_->palmInFlange;
}
Eigen::Isometry3d ArmIk::flangePose(const Eigen::VectorXd& arm) const {
  return impl_->flangePose(arm);
}

std::vector<Eigen::VectorXd> ArmIk::solveFlange(const Eigen::Isometry3d& flange,
                                                std::mt19937_64& rng) const {
  if (impl_->form == Form::kNumerical) return solveNumerically(flange, rng);
  std::vector<Eigen::VectorXd> out;
  // The closed forms verify each branch; whole turns do not change the
  // pose, so their variants are added as they are.
  const std::vector<Eigen::VectorXd> branches = impl_->form == Form::kSphericalWrist
                                                    ? impl_->closedForm(flange)
                                                    : impl_->threeParallel(flange);
  for (const Eigen::VectorXd& arm : branches) impl_->appendTurns(arm, out);
  return out;
}

std::vector<Eigen::VectorXd> ArmIk::solvePalm(const Eigen::Isometry3d& palm,
                                              std::mt19937_64& rng) const {
  return solveFlange(palm * impl_->palmInFlange.inverse(), rng);
}

bool differByWholeTurns(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double tolerance) {
  if (a.size() != b.size()) return false;
  for (Eigen::Index d = 0; d < a.size(); ++d)
    if (std::abs(wrapToPi(a(d) - b(d))) > tolerance) return false;
  return true;
}

std::vector<Eigen::VectorXd> nearestWholeTurns(const std::vector<Eigen::VectorXd>& solutions,
                                               const Eigen::VectorXd& reference,
                                               const Eigen::VectorXd& lower,
                                               const Eigen::VectorXd& upper) {
  constexpr double kLimitTolerance = 1e-9;
  // Each solution moved, joint by joint, to its in-limit whole-turn value
  // nearest the reference (a strictly nearer one only, so ties stay).
  std::vector<Eigen::VectorXd> nearest = solutions;
  std::vector<bool> moved(solutions.size(), false);
  for (std::size_t k = 0; k < nearest.size(); ++k) {
    Eigen::VectorXd& arm = nearest[k];
    for (Eigen::Index d = 0; d < arm.size(); ++d) {
      const double low = lower(d) - kLimitTolerance;
      const double high = upper(d) + kLimitTolerance;
      if (!std::isfinite(low) || !std::isfinite(high) || !std::isfinite(arm(d))) continue;
      double best = arm(d);
      // Every in-limit value arm(d) + 2 pi n, from the lowest up.
      for (double v = arm(d) - 2.0 * M_PI * std::floor((arm(d) - low) / (2.0 * M_PI)); v <= high;
           v += 2.0 * M_PI)
        if (v >= low && std::abs(v - reference(d)) < std::abs(best - reference(d))) best = v;
      if (best != arm(d)) moved[k] = true;
      arm(d) = best;
    }
  }
  // A solution that already was its nearest variant keeps its place; a
  // moved one is kept only when no solution of its class was already
  // there, and once.
  const auto same = [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return (a - b).cwiseAbs().maxCoeff() <= 1e-9;
  };
  // (The unmoved are few: a UR-type arm's 200-odd solutions are the turns
  // of a handful of classes; comparing every pair cost a millisecond.)
  std::vector<const Eigen::VectorXd*> unmoved;
  for (std::size_t k = 0; k < nearest.size(); ++k)
    if (!moved[k]) unmoved.push_back(&nearest[k]);
  std::vector<Eigen::VectorXd> kept;
  for (std::size_t k = 0; k < nearest.size(); ++k) {
    const bool present =
        moved[k] && std::any_of(unmoved.begin(), unmoved.end(),
                                [&](const Eigen::VectorXd* u) { return same(*u, nearest[k]); });
    if (!present && std::none_of(kept.begin(), kept.end(),
                                 [&](const Eigen::VectorXd& a) { return same(a, nearest[k]); }))
      kept.push_back(nearest[k]);
  }
  return kept;
}

std::vector<Eigen::VectorXd> ArmIk::solveNumerically(const Eigen::Isometry3d& flange,
                                                     std::mt19937_64& rng) const {
  const RobotModel& model = impl_->model;
  // A redundant arm reaches a pose along a continuum of configurations:
  // keep those apart by a useful step, not by rounding.
  const double distinct = impl_->dofs() > 6 ? kDistinctRedundantSolutions : 1e-6;
  std::vector<Eigen::VectorXd> out;
  for (int r = 0; r < impl_->options.restarts; ++r) {
    Eigen::VectorXd seed(impl_->dofs());
    for (int d = 0; d < impl_->dofs(); ++d)
      seed(d) = std::uniform_real_distribution<double>(model.lowerLimits()(d),
                                                       model.upperLimits()(d))(rng);
    const std::optional<Eigen::VectorXd> found = impl_->descend(flange, seed);
    if (!found) continue;
    const bool known = std::any_of(out.begin(), out.end(), [&](const Eigen::VectorXd& s) {
      return (s - *found).cwiseAbs().maxCoeff() < distinct;
    });
    if (!known) out.push_back(*found);
  }
  return out;
}

}  // namespace hfts::robot
