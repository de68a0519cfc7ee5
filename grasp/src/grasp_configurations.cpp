#include "grasp/grasp_configurations.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/invalid_argument.h"
#include "robot/kinematics.h"

namespace hfts::grasp {

const char* toString(ConfigurationLabel label) {
  switch (label) {
    case ConfigurationLabel::kCollisionFree:
      return "collision-free";
    case ConfigurationLabel::kColliding:
      return "colliding";
    default:
      return "no kinematic solution";
  }
}

GraspConfigurator::GraspConfigurator(const robot::RobotModel& model, const robot::ArmIk& ik,
                                     const HandReachability& hand, robot::CollisionChecker& checker,
                                     const Eigen::Isometry3d& objectPose,
                                     const Eigen::Isometry3d& robotBase, const HandCloser* closer)
    : model_(model),
      ik_(ik),
      hand_(hand),
      checker_(checker),
      closer_(closer),
      objectInBase_(robotBase.inverse() * objectPose),
      objectInWorld_(objectPose) {}

Eigen::VectorXd openedHand(const robot::RobotModel& model, const Eigen::VectorXd& hand) {
  // A DoF opens its finger when it moves the fingertip against the pad
  // normal (away from the surface the pad pushes on): the sign comes from
  // the fingertip Jacobian at this posture, so no per-robot table is needed.
  // A DoF that drives several fingers (a gripper's mimic jaws) opens them
  // only when it moves each of them mostly along its pad normal, all the
  // same way; one that turns fingers sideways (the SDH knuckle) stays.
  const int arm = model.numArmDofs();
  std::vector<int> joints(static_cast<std::size_t>(model.numDofs()), 0);
  for (const robot::Joint& j : model.joints())
    if (j.dof >= 0) ++joints[static_cast<std::size_t>(j.dof)];
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.numDofs());
  q.tail(hand.size()) = hand;
  const robot::LinkPoses poses = robot::forwardKinematics(model, q);
  Eigen::VectorXd towardsPad = Eigen::VectorXd::Zero(hand.size());
  std::vector<bool> alongPads(static_cast<std::size_t>(hand.size()), true);
  std::vector<int> signs(static_cast<std::size_t>(hand.size()), 0);
  for (const robot::Fingertip& tip : model.fingertips()) {
    const auto j = jacobian(model, poses, tip.link, tip.point);
    const Eigen::Vector3d pad = poses[static_cast<std::size_t>(tip.link)].linear() * tip.normal;
    const Eigen::MatrixXd motion = j.topRows<3>().rightCols(hand.size());
    const Eigen::VectorXd along = (pad.transpose() * motion).transpose();
    towardsPad += along;
    for (Eigen::Index h = 0; h < hand.size(); ++h) {
      const double moved = motion.col(h).norm();
      if (moved < 1e-12) continue;  // this finger does not move with DoF h
      const auto k = static_cast<std::size_t>(h);
      const int sign = along(h) > 0.0 ? 1 : -1;
      if (std::abs(along(h)) < 0.5 * moved || (signs[k] != 0 && signs[k] != sign))
        alongPads[k] = false;
      signs[k] = sign;
    }
  }
  Eigen::VectorXd open = hand;
  for (Eigen::Index h = 0; h < hand.size(); ++h) {
    const auto k = static_cast<std::size_t>(h);
    const bool singleFinger = joints[static_cast<std::size_t>(arm + h)] == 1;
    if (!(singleFinger || alongPads[k]) || towardsPad(h) == 0.0) continue;
    const double step = towardsPad(h) > 0.0 ? -model.pregraspOffset() : model.pregraspOffset();
    open(h) =
        std::clamp(hand(h) + step, model.lowerLimits()(arm + h), model.upperLimits()(arm + h));
  }
  return open;
}

Eigen::VectorXd GraspConfigurator::openedHand(const Eigen::VectorXd& hand) const {
  return grasp::openedHand(model_, hand);
}

GraspConfigurations GraspConfigurator::configure(const GraspContacts& grasp, std::mt19937_64& rng,
                                                 bool turn, bool close) {
  return configure(grasp, hand_.query(grasp.positions, grasp.outward_normals), rng, turn, close);
}

std::vector<GraspConfigurations> GraspConfigurator::configureOtherHands(const GraspContacts& grasp,
                                                                        double maxPositionError,
                                                                        std::mt19937_64& rng,
                                                                        bool close) {
  // The posture configure() uses (the same query, so the same answer).
  return configureOtherHands(grasp, hand_.query(grasp.positions, grasp.outward_normals),
                             maxPositionError, rng, close);
}

std::vector<GraspConfigurations> GraspConfigurator::configureOtherHands(const GraspContacts& grasp,
                                                                        const HandQuery& used,
                                                                        double maxPositionError,
                                                                        std::mt19937_64& rng,
                                                                        bool close) {
  constexpr double kSamePosture = 0.05;  // rad
  std::vector<GraspConfigurations> out;
  for (HandQuery& other : hand_.queryAlternatives(grasp.positions, grasp.outward_normals,
                                                  maxPositionError, kSamePosture))
    if (!samePosture(other, used, kSamePosture))
      out.push_back(configure(grasp, std::move(other), rng, true, close));
  return out;
}

void GraspConfigurator::setTurns(int turns) {
  if (turns < 1) throw InvalidArgument("turns", "must be >= 1, got " + std::to_string(turns));
  turns_ = turns;
}

void GraspConfigurator::setArmReference(const Eigen::VectorXd& arm) {
  if (arm.size() != model_.numArmDofs())
    throw InvalidArgument("arm", std::to_string(model_.numArmDofs()) + " values expected, got " +
                                     std::to_string(arm.size()));
  if (!arm.allFinite()) throw InvalidArgument("arm", "values must be finite");
  reference_ = arm;
}

void GraspConfigurator::keepNearestTurns(std::vector<Eigen::VectorXd>& arms) const {
  arms = robot::nearestWholeTurns(arms, reference_, model_.lowerLimits().head(reference_.size()),
                                  model_.upperLimits().head(reference_.size()));
}

GraspConfigurations GraspConfigurator::configure(const GraspContacts& grasp, HandQuery hand,
                                                 std::mt19937_64& rng, bool turn, bool close) {
  GraspConfigurations out;
  out.hand = std::move(hand);
  if (turn && out.hand.free_turn && turns_ > 1)
    configureTurns(grasp, close, out, rng);
  else
    appendArmConfigurations(grasp, out.hand, out.hand.palm_pose, close, rng, out.configurations);
  if (out.configurations.empty()) out.configurations.emplace_back();
  return out;
}

void GraspConfigurator::configureTurns(const GraspContacts& grasp, bool close,
                                       GraspConfigurations& out, std::mt19937_64& rng) {
  const double step = 2.0 * M_PI / turns_;
  const double start = std::uniform_real_distribution<double>(0.0, step)(rng);
  const auto isFree = [](const GraspConfiguration& c) {
    return c.label == ConfigurationLabel::kCollisionFree;
  };
  out.turns_tried = 0;
  for (int k = 0; k < turns_; ++k) {
    ++out.turns_tried;
    const Eigen::Isometry3d palm = turnedPalm(out.hand, start + k * step);
    if (checker_.handInCollision(objectInWorld_ * palm, out.hand.hand_configuration,
                                 robot::CollisionRequest::obstaclesOnly())) {
      ++out.turns_blocked;
      continue;
    }
    const std::size_t before = out.configurations.size();
    appendArmConfigurations(grasp, out.hand, palm, close, rng, out.configurations);
    if (std::any_of(out.configurations.begin() + static_cast<std::ptrdiff_t>(before),
                    out.configurations.end(), isFree))
      return;
  }
  // Every turn's hand meets an obstacle: a colliding configuration still
  // tells the rating how close the grasp is to C_free (Sec. III-B.3).
  if (out.configurations.empty())
    appendArmConfigurations(grasp, out.hand, turnedPalm(out.hand, start), close, rng,
                            out.configurations);
}

double GraspConfigurator::fingertipError(const GraspContacts& grasp, const HandQuery& hand,
                                         const Eigen::Isometry3d& palm) const {
  Eigen::VectorXd q = model_.home();
  q.tail(model_.numHandDofs()) = hand.hand_configuration;
  const robot::LinkPoses poses = robot::forwardKinematics(model_, q);
  const Eigen::Isometry3d toObject =
      palm * poses[static_cast<std::size_t>(model_.palmLink())].inverse();
  double error = 0.0;
  for (Eigen::Index i = 0; i < grasp.positions.cols(); ++i) {
    const int finger = hand.finger_of_contact[static_cast<std::size_t>(i)];
    const robot::Fingertip& tip = model_.fingertips()[static_cast<std::size_t>(finger)];
    const Eigen::Vector3d at = toObject * (poses[static_cast<std::size_t>(tip.link)] * tip.point);
    error = std::max(error, (at - grasp.positions.col(i)).norm());
  }
  return error;
}

void GraspConfigurator::appendArmConfigurations(const GraspContacts& grasp, const HandQuery& hand,
                                                const Eigen::Isometry3d& palm, bool close,
                                                std::mt19937_64& rng,
                                                std::vector<GraspConfiguration>& out) {
  const Eigen::VectorXd opened = openedHand(hand.hand_configuration);
  const double fingertipError = this->fingertipError(grasp, hand, palm);
  const std::size_t first = out.size();
  appendArms(palm, hand.hand_configuration, opened, nullptr, rng, out);
  // Closing costs milliseconds: only for a grasp the hand reaches, with an
  // arm solution whose pre-grasp is free.
  const bool worthClosing = close && closer_ != nullptr && fingertipError <= maxClosingError_ &&
                            std::any_of(out.begin() + static_cast<std::ptrdiff_t>(first), out.end(),
                                        [](const GraspConfiguration& c) {
                                          return c.label == ConfigurationLabel::kCollisionFree;
                                        });
  if (worthClosing) {
    const auto closure =
        std::make_shared<const HandClosure>(closer_->close(palm, opened, hand.hand_configuration));
    out.resize(first);
    // The closing may have moved the palm (a gripper centring its jaws).
    appendArms(closure->palm, closure->hand, opened, closure, rng, out);
  }
  for (std::size_t k = first; k < out.size(); ++k) out[k].fingertip_error = fingertipError;
}

void GraspConfigurator::appendArms(const Eigen::Isometry3d& palm, const Eigen::VectorXd& graspHand,
                                   const Eigen::VectorXd& opened,
                                   std::shared_ptr<const HandClosure> closure, std::mt19937_64& rng,
                                   std::vector<GraspConfiguration>& out) {
  std::vector<Eigen::VectorXd> arms = ik_.solvePalm(objectInBase_ * palm, rng);
  if (reference_.size() > 0) keepNearestTurns(arms);
  const std::size_t first = out.size();
  for (std::size_t k = 0; k < arms.size(); ++k) {
    const Eigen::VectorXd& arm = arms[k];
    // A closed form gives up to 2^5 whole-turn variants of a branch (the
    // UR5e's +-360 degree joints): check one of them, copy the others.
    const auto twin = std::find_if(
        arms.begin(), arms.begin() + static_cast<std::ptrdiff_t>(k),
        [&](const Eigen::VectorXd& other) { return robot::differByWholeTurns(arm, other); });
    if (twin != arms.begin() + static_cast<std::ptrdiff_t>(k)) {
      const std::size_t same = first + static_cast<std::size_t>(twin - arms.begin());
      GraspConfiguration c = out[same];
      c.grasp.head(arm.size()) = arm;
      c.pregrasp.head(arm.size()) = arm;
      c.same_poses_as = static_cast<int>(same);
      out.push_back(std::move(c));
      continue;
    }
    GraspConfiguration c;
    c.grasp.resize(model_.numDofs());
    c.grasp << arm, graspHand;
    c.pregrasp.resize(model_.numDofs());
    c.pregrasp << arm, opened;
    c.closure = closure;
    const bool free =
        !checker_.inCollision(c.pregrasp, &c.collision) &&
        !(closure && checker_.inCollision(c.grasp, robot::CollisionRequest::grasp(), &c.collision));
    c.label = free ? ConfigurationLabel::kCollisionFree : ConfigurationLabel::kColliding;
    if (free) c.collision = {};
    out.push_back(std::move(c));
  }
}

void GraspConfigurator::setMaxClosingError(double error) {
  if (!(error > 0.0)) throw InvalidArgument("max_fingertip_error", "must be > 0");
  maxClosingError_ = error;
}

GraspConfigurations GraspConfigurator::configure(const HftsSpace& space, const HftsNode& node,
                                                 std::mt19937_64& rng, bool turn, bool close) {
  return configure(space.representative(node), rng, turn, close);
}

}  // namespace hfts::grasp
