#include "hand_alignment.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <cmath>

namespace hfts::grasp::hand {
namespace {

/// Position and normal residual per finger: 6 m rows, a compile-time
/// size (Rows) in the linear algebra of a step, so that its products
/// unroll and vectorise as for a fixed hand (solveStep dispatches on m).
template <int Rows>
using Residuals = Eigen::Matrix<double, Rows, 1>;
/// Row-major, so that the Cholesky inner loops run over contiguous rows.
using Square = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor, kMaxDofs + 3,
                             kMaxDofs + 3>;
using Step = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxDofs + 3, 1>;

/// Below this cost (R ~ 1e-9 m) a triple counts as exactly reached.
constexpr double kReachedCost = 1e-18;
/// An accepted step that lowers the cost by less than this fraction ends
/// the refinement: R would change by less than 0.5%.
constexpr double kUsefulDecrease = 1e-2;

/// The weighted cross-covariance H (the best rotation maximises tr(R H))
/// and the rotation-independent part of the cost.
struct Covariance {
  Eigen::Matrix3d h;
  double constant = 0.0;
};

Covariance covariance(const Tips& positions, const Tips& normals, const Target& target) {
  const Tips p = positions.colwise() - positions.rowwise().mean();
  const Tips c = target.contacts.colwise() - target.contacts.rowwise().mean();
  const double l2 = target.lambda * target.lambda;
  return {p * c.transpose() + l2 * normals * target.pad_normals.transpose(),
          p.squaredNorm() + c.squaredNorm() +
              l2 * (normals.squaredNorm() + target.pad_normals.squaredNorm())};
}

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

/// The linearised problem in the palm frame, with the translation
/// eliminated: it is optimal in closed form (the centroids coincide), so
/// position residuals and their Jacobians are centred over the fingers.
/// Rows: 3 position and 3 normal residuals per finger. Columns: the hand
/// DoF, then a rotation of the palm about the fingertips' centroid.
template <int Rows>
using Jacobian = Eigen::Matrix<double, Rows, Eigen::Dynamic, 0, Rows, kMaxDofs + 3>;

template <int Rows>
void linearize(const TipState& tips, const Alignment& pose, const Target& target,
               Residuals<Rows>& r, Jacobian<Rows>& j) {
  constexpr int fingers = Rows / 6;
  const auto dofs = tips.d_positions.cols();
  const Eigen::Matrix3d back = pose.rotation.transpose();
  const Tips contacts = back * (target.contacts.colwise() - pose.translation);
  const Tips pads = back * target.pad_normals;
  const Eigen::Vector3d tipMean = tips.positions.rowwise().mean();
  const Eigen::Vector3d residualMean = tipMean - contacts.rowwise().mean();
  Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxDofs> dMean =
      tips.d_positions.middleRows<3>(0);
  for (int i = 1; i < fingers; ++i) dMean += tips.d_positions.middleRows<3>(3 * i);
  dMean /= static_cast<double>(fingers);
  j.resize(Rows, dofs + 3);
  for (int i = 0; i < fingers; ++i) {
    const int p = 3 * i, n = 3 * fingers + 3 * i;
    r.template segment<3>(p) = tips.positions.col(i) - contacts.col(i) - residualMean;
    r.template segment<3>(n) = target.lambda * (tips.normals.col(i) - pads.col(i));
    j.block(p, 0, 3, dofs) = tips.d_positions.middleRows<3>(p) - dMean;
    j.block(n, 0, 3, dofs) = target.lambda * tips.d_normals.middleRows<3>(p);
    j.template block<3, 3>(p, dofs) = -skew(tips.positions.col(i) - tipMean);
    j.template block<3, 3>(n, dofs) = -target.lambda * skew(tips.normals.col(i));
  }
}

/// Solves a x = b in place for symmetric positive definite a (Cholesky,
/// lower triangle). Hand-written: at this size Eigen's general paths cost
/// more than the arithmetic. False when a is not positive definite.
bool solvePositiveDefinite(Square& a, Step& b) {
  const Eigen::Index n = a.rows();
  for (Eigen::Index k = 0; k < n; ++k) {
    double d = a(k, k);
    for (Eigen::Index m = 0; m < k; ++m) d -= a(k, m) * a(k, m);
    if (!(d > 0.0)) return false;
    a(k, k) = std::sqrt(d);
    for (Eigen::Index i = k + 1; i < n; ++i) {
      double v = a(i, k);
      for (Eigen::Index m = 0; m < k; ++m) v -= a(i, m) * a(k, m);
      a(i, k) = v / a(k, k);
    }
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index m = 0; m < i; ++m) b(i) -= a(i, m) * b(m);
    b(i) /= a(i, i);
  }
  for (Eigen::Index i = n - 1; i >= 0; --i) {
    for (Eigen::Index m = i + 1; m < n; ++m) b(i) -= a(m, i) * b(m);
    b(i) /= a(i, i);
  }
  return true;
}

/// One damped Gauss-Newton step (Marquardt scaling). Joints at a limit
/// that the gradient pushes further out are held, so clamping does not
/// stall the other joints. False when the system cannot be solved.
template <int Rows>
bool dampedStep(const Residuals<Rows>& r, Jacobian<Rows>& j, const HandVector& q,
                const HandChains& chains, double mu, Step& step) {
  step.noalias() = -(j.transpose() * r);
  for (Eigen::Index d = 0; d < q.size(); ++d) {
    const bool atLower = q(d) <= chains.lower()(d) && step(d) < 0;
    const bool atUpper = q(d) >= chains.upper()(d) && step(d) > 0;
    if (atLower || atUpper) {
      j.col(d).setZero();
      step(d) = 0.0;
    }
  }
  Square a(j.cols(), j.cols());
  for (Eigen::Index c = 0; c < j.cols(); ++c)
    for (Eigen::Index k = c; k < j.cols(); ++k) a(k, c) = j.col(k).dot(j.col(c));  // lower
  for (Eigen::Index k = 0; k < a.rows(); ++k)
    a(k, k) = a(k, k) > 0 ? a(k, k) * (1.0 + mu) : 1.0;  // held or inert variables stay put
  return solvePositiveDefinite(a, step);
}

/// The damped step of the linearised problem at `tips` for m = Rows / 6
/// fingers.
template <int Rows>
bool solveStep(const TipState& tips, const Alignment& pose, const Target& target,
               const HandVector& q, const HandChains& chains, double mu, Step& step) {
  Residuals<Rows> r;
  Jacobian<Rows> j;
  linearize<Rows>(tips, pose, target, r, j);
  return dampedStep<Rows>(r, j, q, chains, mu, step);
}

bool solveStep(const TipState& tips, const Alignment& pose, const Target& target,
               const HandVector& q, const HandChains& chains, double mu, Step& step) {
  static_assert(robot::hand::kMinFingers == 2 && robot::hand::kMaxFingers == 4);
  switch (tips.positions.cols()) {
    case 2:
      return solveStep<12>(tips, pose, target, q, chains, mu, step);
    case 3:
      return solveStep<18>(tips, pose, target, q, chains, mu, step);
    default:
      return solveStep<24>(tips, pose, target, q, chains, mu, step);
  }
}

/// exp(skew(w)) by Rodrigues' formula.
Eigen::Matrix3d rotationOf(const Eigen::Vector3d& w) {
  const double angle2 = w.squaredNorm();
  if (angle2 < 1e-24) return Eigen::Matrix3d::Identity() + skew(w);
  const double angle = std::sqrt(angle2);
  const Eigen::Matrix3d k = skew(w);
  return Eigen::Matrix3d::Identity() + (std::sin(angle) / angle) * k +
         ((1.0 - std::cos(angle)) / angle2) * (k * k);
}

/// The proper rotation maximising tr(R H) from the SVD H = U S V^T:
/// V diag(1, 1, det(V U^T)) U^T. When H has rank one (a gripper whose pads
/// face along the line through its fingertips) only R u1 = v1 is fixed and
/// the SVD's choice of the other columns picks one of the equally good
/// turns about v1.
Eigen::Matrix3d rotationBySvd(const Eigen::Matrix3d& h) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d v = svd.matrixV();
  if ((v * svd.matrixU().transpose()).determinant() < 0) v.col(2) = -v.col(2);
  return v * svd.matrixU().transpose();
}

/// The proper rotation maximising tr(R H) (Kabsch): R = V diag(1, 1, d) U^T
/// for H = U S V^T. V and S come from the closed-form eigen decomposition of
/// H^T H, which is several times faster than a 3 x 3 SVD; U's third column
/// is the cross product of the first two, so d = det V.
Eigen::Matrix3d bestRotation(const Eigen::Matrix3d& h) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
  eigen.computeDirect(h.transpose() * h);
  const Eigen::Vector3d s = eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt();  // ascending
  if (!(s(1) > 1e-9 * s(2))) return rotationBySvd(h);                       // rank < 2: not unique
  const Eigen::Matrix3d& vs = eigen.eigenvectors();
  const Eigen::Vector3d va = vs.col(2), vb = vs.col(1), vc = vs.col(0);
  const Eigen::Vector3d ua = (h * va).normalized();
  const Eigen::Vector3d hb = h * vb;
  const Eigen::Vector3d ub = (hb - ua.dot(hb) * ua).normalized();
  const double d = va.cross(vb).dot(vc) < 0 ? -1.0 : 1.0;
  const Eigen::Matrix3d r =
      va * ua.transpose() + vb * ub.transpose() + d * vc * ua.cross(ub).transpose();
  // The closed form resolves a double eigenvalue 0 of H^T H only to about
  // machine epsilon^(1/4) of the largest: a rank-one H can pass the test
  // above, and then ub is rounding noise, or 0 and r no rotation at all.
  if ((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6)
    return rotationBySvd(h);
  return r;
}

}  // namespace

double alignmentCost(const Tips& positions, const Tips& normals, const Target& target) {
  const Covariance cov = covariance(positions, normals, target);
  // max tr(R H) over proper rotations = s1 + s2 + sign(det H) s3.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
  eigen.computeDirect(cov.h.transpose() * cov.h, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d s = eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt();  // ascending
  const double trace = s(2) + s(1) + (cov.h.determinant() < 0 ? -s(0) : s(0));
  return std::max(0.0, cov.constant - 2.0 * trace);
}

Alignment align(const Tips& positions, const Tips& normals, const Target& target) {
  Alignment out;
  out.rotation = bestRotation(covariance(positions, normals, target).h);
  out.translation = target.contacts.rowwise().mean() - out.rotation * positions.rowwise().mean();
  out.cost = costOf(positions, normals, target, out.rotation, out.translation);
  return out;
}

double costOf(const Tips& positions, const Tips& normals, const Target& target,
              const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation) {
  // Column by column: fixed-size vector arithmetic, whatever the finger count.
  const double l2 = target.lambda * target.lambda;
  double cost = 0.0;
  for (Eigen::Index f = 0; f < positions.cols(); ++f) {
    const Eigen::Vector3d p = rotation * positions.col(f) + translation - target.contacts.col(f);
    const Eigen::Vector3d n = rotation * normals.col(f) - target.pad_normals.col(f);
    cost += p.squaredNorm() + l2 * n.squaredNorm();
  }
  return cost;
}

Refinement::Refinement(const HandChains& chains, const HandMapOptions& posture,
                       const Target& target, const HandVector& q0)
    : chains_(&chains), posture_(&posture), target_(target) {
  chains.evaluate(q0.data(), states_[current_], true);
  best_ = {q0, align(tips().positions, tips().normals, target)};
  finished_ = best_.pose.cost <= kReachedCost;
}

void Refinement::track(int stages, int iterationsPerStage) {
  const Target goal = target_;
  const Tips startP = (best_.pose.rotation * tips().positions).colwise() + best_.pose.translation;
  const Tips startN = best_.pose.rotation * tips().normals;
  for (int k = 1; k <= stages; ++k) {
    const double tau = static_cast<double>(k) / (stages + 1);
    target_.contacts = (1 - tau) * startP + tau * goal.contacts;
    for (Eigen::Index f = 0; f < goal.contacts.cols(); ++f) {
      // Normalised blend; opposite normals have no midpoint, take the goal.
      const Eigen::Vector3d n = (1 - tau) * startN.col(f) + tau * goal.pad_normals.col(f);
      target_.pad_normals.col(f) = n.norm() > 1e-6 ? n.normalized() : goal.pad_normals.col(f);
    }
    retarget();
    iterate(iterationsPerStage);
  }
  target_ = goal;
  retarget();
}

void Refinement::retarget() {
  best_.pose.cost = costOf(tips().positions, tips().normals, target_, best_.pose.rotation,
                           best_.pose.translation);
  finished_ = best_.pose.cost <= kReachedCost;
  mu_ = 1e-3;
}

void Refinement::iterate(int iterations) {
  for (int i = 0; i < iterations && !finished_; ++i) {
    const double before = best_.pose.cost;
    if (step() && best_.pose.cost > before * (1.0 - kUsefulDecrease)) finished_ = true;
    if (best_.pose.cost <= kReachedCost || mu_ > 1e10) finished_ = true;
  }
}

/// One Levenberg-Marquardt iteration; true when the step was accepted.
bool Refinement::step() {
  Step delta;
  if (!solveStep(tips(), best_.pose, target_, best_.q, *chains_, mu_, delta)) {
    mu_ *= 8.0;
    return false;
  }
  const Eigen::Index dofs = best_.q.size();
  Solution trial;
  trial.q = (best_.q + delta.head(dofs)).cwiseMax(chains_->lower()).cwiseMin(chains_->upper());
  trial.pose.rotation = best_.pose.rotation * rotationOf(delta.tail<3>());
  TipState& tips = states_[1 - current_];
  chains_->evaluate(trial.q.data(), tips, false);
  trial.pose.translation =
      target_.contacts.rowwise().mean() - trial.pose.rotation * tips.positions.rowwise().mean();
  trial.pose.cost =
      costOf(tips.positions, tips.normals, target_, trial.pose.rotation, trial.pose.translation);
  if (trial.pose.cost < best_.pose.cost &&
      isGraspPosture(tips.positions, tips.normals, *posture_)) {
    best_ = trial;
    current_ = 1 - current_;
    chains_->jacobians(states_[current_]);
    mu_ = std::max(mu_ * 0.3, 1e-9);
    return true;
  }
  mu_ *= 8.0;
  return false;
}

}  // namespace hfts::grasp::hand
