#include "grasp/grasp_configurations.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "hfts_db/invalid_argument.h"
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
                                     const Eigen::Isometry3d& robotBase)
    : model_(model),
      ik_(ik),
      hand_(hand),
      checker_(checker),
      objectInBase_(robotBase.inverse() * objectPose),
      objectInWorld_(objectPose) {
  std::vector<int> joints(static_cast<std::size_t>(model.numDofs()), 0);
  for (const robot::Joint& j : model.joints())
    if (j.dof >= 0) ++joints[static_cast<std::size_t>(j.dof)];
  for (int d = model.numArmDofs(); d < model.numDofs(); ++d)
    singleFinger_.push_back(joints[static_cast<std::size_t>(d)] == 1);
}

Eigen::VectorXd GraspConfigurator::openedHand(const Eigen::VectorXd& hand) const {
  // A DoF opens its finger when it moves the fingertip against the pad
  // normal (away from the surface the pad pushes on): the sign comes from
  // the fingertip Jacobian at this posture, so no per-robot table is needed.
  // A DoF that drives several fingers (a gripper's mimic jaws) opens them
  // only when it moves each of them mostly along its pad normal, all the
  // same way; one that turns fingers sideways (the SDH knuckle) stays.
  const int arm = model_.numArmDofs();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model_.numDofs());
  q.tail(hand.size()) = hand;
  const robot::LinkPoses poses = robot::forwardKinematics(model_, q);
  Eigen::VectorXd towardsPad = Eigen::VectorXd::Zero(hand.size());
  std::vector<bool> alongPads(static_cast<std::size_t>(hand.size()), true);
  std::vector<int> signs(static_cast<std::size_t>(hand.size()), 0);
  for (const robot::Fingertip& tip : model_.fingertips()) {
    const auto j = jacobian(model_, poses, tip.link, tip.point);
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
    if (!(singleFinger_[k] || alongPads[k]) || towardsPad(h) == 0.0) continue;
    const double step = towardsPad(h) > 0.0 ? -model_.pregraspOffset() : model_.pregraspOffset();
    open(h) =
        std::clamp(hand(h) + step, model_.lowerLimits()(arm + h), model_.upperLimits()(arm + h));
  }
  return open;
}

GraspConfigurations GraspConfigurator::configure(const GraspContacts& grasp, std::mt19937_64& rng,
                                                 bool turn) {
  return configure(grasp, hand_.query(grasp.positions, grasp.outward_normals), rng, turn);
}

std::vector<GraspConfigurations> GraspConfigurator::configureOtherHands(const GraspContacts& grasp,
                                                                        double maxPositionError,
                                                                        std::mt19937_64& rng) {
  // The posture configure() uses (the same query, so the same answer).
  return configureOtherHands(grasp, hand_.query(grasp.positions, grasp.outward_normals),
                             maxPositionError, rng);
}

std::vector<GraspConfigurations> GraspConfigurator::configureOtherHands(const GraspContacts& grasp,
                                                                        const HandQuery& used,
                                                                        double maxPositionError,
                                                                        std::mt19937_64& rng) {
  constexpr double kSamePosture = 0.05;  // rad
  std::vector<GraspConfigurations> out;
  for (HandQuery& other : hand_.queryAlternatives(grasp.positions, grasp.outward_normals,
                                                  maxPositionError, kSamePosture))
    if (!samePosture(other, used, kSamePosture))
      out.push_back(configure(grasp, std::move(other), rng, true));
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
                                                 std::mt19937_64& rng, bool turn) {
  GraspConfigurations out;
  out.hand = std::move(hand);
  if (turn && out.hand.free_turn && turns_ > 1)
    configureTurns(grasp, out, rng);
  else
    appendArmConfigurations(grasp, out.hand, out.hand.palm_pose, rng, out.configurations);
  if (out.configurations.empty()) out.configurations.emplace_back();
  return out;
}

void GraspConfigurator::configureTurns(const GraspContacts& grasp, GraspConfigurations& out,
                                       std::mt19937_64& rng) {
  const double step = 2.0 * M_PI / turns_;
  const double start = std::uniform_real_distribution<double>(0.0, step)(rng);
  const auto isFree = [](const GraspConfiguration& c) {
    return c.label == ConfigurationLabel::kCollisionFree;
  };
  out.turns_tried = 0;
  for (int k = 0; k < turns_; ++k) {
    ++out.turns_tried;
    const Eigen::Isometry3d palm = turnedPalm(out.hand, start + k * step);
    if (checker_.handTouchesObstacles(objectInWorld_ * palm, out.hand.hand_configuration)) {
      ++out.turns_blocked;
      continue;
    }
    const std::size_t before = out.configurations.size();
    appendArmConfigurations(grasp, out.hand, palm, rng, out.configurations);
    if (std::any_of(out.configurations.begin() + static_cast<std::ptrdiff_t>(before),
                    out.configurations.end(), isFree))
      return;
  }
  // Every turn's hand meets an obstacle: a colliding configuration still
  // tells the rating how close the grasp is to C_free (Sec. III-B.3).
  if (out.configurations.empty())
    appendArmConfigurations(grasp, out.hand, turnedPalm(out.hand, start), rng, out.configurations);
}

void GraspConfigurator::appendArmConfigurations(const GraspContacts& grasp, const HandQuery& hand,
                                                const Eigen::Isometry3d& palm, std::mt19937_64& rng,
                                                std::vector<GraspConfiguration>& out) {
  std::vector<Eigen::VectorXd> arms = ik_.solvePalm(objectInBase_ * palm, rng);
  if (reference_.size() > 0) keepNearestTurns(arms);
  const Eigen::Matrix3Xd contacts = objectInBase_ * grasp.positions;
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
    c.grasp << arm, hand.hand_configuration;
    c.pregrasp = c.grasp;
    c.pregrasp.tail(model_.numHandDofs()) = openedHand(hand.hand_configuration);
    const robot::FingertipFrames tips =
        robot::fingertipFrames(model_, robot::forwardKinematics(model_, c.grasp));
    for (Eigen::Index i = 0; i < contacts.cols(); ++i) {
      const int finger = hand.finger_of_contact[static_cast<std::size_t>(i)];
      c.fingertip_error =
          std::max(c.fingertip_error, (tips.positions.col(finger) - contacts.col(i)).norm());
    }
    const bool free = !checker_.inCollision(c.pregrasp, &c.collision) &&
                      !checker_.inCollisionAllowingFingertipContact(c.grasp, &c.collision);
    c.label = free ? ConfigurationLabel::kCollisionFree : ConfigurationLabel::kColliding;
    if (free) c.collision = {};
    out.push_back(std::move(c));
  }
}

GraspConfigurations GraspConfigurator::configure(const HftsSpace& space, const HftsNode& node,
                                                 std::mt19937_64& rng, bool turn) {
  return configure(space.representative(node), rng, turn);
}

}  // namespace hfts::grasp
