// One run of the protocol: settle, close, lift, hold, disturb (docs/physics.md).
#include "grasp_trial.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

namespace hfts::physics {
namespace {

constexpr double kGravity = 9.81;

std::string millimetres(double metres) {
  return std::to_string(static_cast<long>(std::lround(metres * 1000.0))) + " mm";
}

std::string degrees(double radians) {
  return std::to_string(static_cast<long>(std::lround(radians * 180.0 / M_PI))) + " deg";
}

int stepsOf(double seconds, double timestep) {
  return static_cast<int>(std::lround(seconds / timestep));
}

class Trial {
 public:
  Trial(const mjModel& model, const TrialPlan& plan, std::vector<MotionSample>* motion)
      : m_(model), plan_(plan), data_(makeData(model)), motion_(motion) {}

  TrialResult run(const std::string& name) {
    result_.name = name;
    mjData& d = *data_;
    setRobotConfiguration(d, plan_.index, plan_.pregrasp);
    setObjectPose(d, plan_.index, plan_.object_pose);
    mj_forward(&m_, &d);
    try {
      result_.held = settleAndClose() && lift() && hold() && disturb();
    } catch (const Stopped&) {
      result_.held = false;
      result_.stopped = true;
      result_.failure = "stopped";
    }
    result_.simulated_time = elapsed_;
    if (!result_.held && !result_.stopped && !held_through_hold_)
      result_.fingers_in_contact = fingersInContact();
    return result_;
  }

  /// Settle, close, the plan's lift, carry and descent tracked in the
  /// palm, the opening and the retreat as planned, then still.
  PlaceVerdict runPlace() {
    PlaceVerdict verdict;
    mjData& d = *data_;
    setRobotConfiguration(d, plan_.index, plan_.pregrasp);
    setObjectPose(d, plan_.index, plan_.object_pose);
    mj_forward(&m_, &d);
    try {
      verdict.held = settleAndClose() && lift() && carry();
      const bool ran = verdict.held && release() && rest();
      verdict.placed = ran && rest_displacement_ <= plan_.rest.max_displacement &&
                       rest_rotation_ <= plan_.rest.max_rotation;
      verdict.stood = ran && stand_displacement_ <= plan_.rest.max_displacement &&
                      stand_rotation_ <= plan_.rest.max_rotation;
    } catch (const Stopped&) {
      result_.failure = "stopped";
    }
    verdict.failure = result_.failure;
    verdict.max_displacement = result_.max_displacement;
    verdict.max_rotation = result_.max_rotation;
    verdict.rest_displacement = rest_displacement_;
    verdict.stand_displacement = stand_displacement_;
    verdict.stand_rotation = stand_rotation_;
    verdict.rest_rotation = rest_rotation_;
    verdict.place_displacement = place_displacement_;
    verdict.place_rotation = place_rotation_;
    verdict.simulated_time = elapsed_;
    return verdict;
  }

 private:
  /// The plan's trajectory at time t (s from its start), linear between
  /// its samples.
  Eigen::VectorXd planned(double t) const {
    const PlaceMotion& m = *plan_.place;
    const auto after = std::upper_bound(m.times.begin(), m.times.end(), t);
    if (after == m.times.begin()) return m.positions.front();
    if (after == m.times.end()) return m.positions.back();
    const auto k = static_cast<std::size_t>(after - m.times.begin());
    const double f = (t - m.times[k - 1]) / (m.times[k] - m.times[k - 1]);
    return (1 - f) * m.positions[k - 1] + f * m.positions[k];
  }

  /// The carry and the descent: the trajectory up to the release, the hand
  /// servos held as they closed, the object tracked in the palm.
  bool carry() {
    const PlaceMotion& m = *plan_.place;
    const int n = stepsOf(m.release_start - m.times.front(), options().timestep);
    Eigen::VectorXd target = m.positions.front();
    for (int s = 1; s <= n; ++s) {
      target = planned(m.times.front() + s * options().timestep);
      target.tail(plan_.robot->numHandDofs()) = hand_target_;
      if (!stepAndTrack(target, "carry")) return false;
    }
    // The servos lag behind a fast trajectory: the arm comes to rest at
    // the place before the hand opens, as a controller waits for it.
    for (int s = 0; s < stepsOf(options().settle_time, options().timestep); ++s)
      if (!stepAndTrack(target, "carry")) return false;
    released_ = bodyPose(*data_, plan_.index.object_body);
    return true;
  }

  /// The hand opens and the arm retreats as planned, the object watched
  /// from where the hand let go of it.
  bool release() {
    const PlaceMotion& m = *plan_.place;
    const int n = stepsOf(m.times.back() - m.release_start, options().timestep);
    for (int s = 1; s <= n; ++s)
      if (!stepAndWatch(planned(m.release_start + s * options().timestep), "release")) return false;
    return true;
  }

  /// Still for the rest check's duration, the object watched from where it
  /// was released and from where it was when the retreat ended; then how
  /// far it is from where the plan put it.
  bool rest() {
    const Eigen::VectorXd target = plan_.place->positions.back();
    const Eigen::Isometry3d start = bodyPose(*data_, plan_.index.object_body);
    for (int s = 0; s < stepsOf(plan_.rest.duration, options().timestep); ++s) {
      if (!stepAndWatch(target, "rest")) return false;
      const Eigen::Isometry3d now = bodyPose(*data_, plan_.index.object_body);
      stand_displacement_ =
          std::max(stand_displacement_, (now * centreOfMass() - start * centreOfMass()).norm());
      stand_rotation_ = std::max(
          stand_rotation_, Eigen::AngleAxisd(start.linear().transpose() * now.linear()).angle());
    }
    const Eigen::Isometry3d now = bodyPose(*data_, plan_.index.object_body);
    const Eigen::Isometry3d& planned = plan_.place->place_pose;
    place_displacement_ = (now * centreOfMass() - planned * centreOfMass()).norm();
    place_rotation_ = Eigen::AngleAxisd(planned.linear().transpose() * now.linear()).angle();
    return true;
  }

  /// One step towards `target` with the object watched from where it was
  /// released: the first time it goes beyond the rest check's limits
  /// (RestOptions) is the failure; the simulation goes on to see whether it
  /// stands after the retreat. False only when the simulation diverged.
  bool stepAndWatch(const Eigen::VectorXd& target, const std::string& phase) {
    step(target, phase.c_str());
    if (unstable(phase)) return false;
    const Eigen::Isometry3d now = bodyPose(*data_, plan_.index.object_body);
    const double moved = (now * centreOfMass() - released_ * centreOfMass()).norm();
    const double turned = Eigen::AngleAxisd(released_.linear().transpose() * now.linear()).angle();
    rest_displacement_ = std::max(rest_displacement_, moved);
    rest_rotation_ = std::max(rest_rotation_, turned);
    if (moved > plan_.rest.max_displacement)
      fail(phase + ": object moved " + millimetres(moved) + " from where it was released");
    if (turned > plan_.rest.max_rotation)
      fail(phase + ": object turned " + degrees(turned) + " from where it was released");
    return true;
  }

  /// The object's centre of mass in its body frame.
  Eigen::Vector3d centreOfMass() const {
    const int body = plan_.index.object_body;
    return {m_.body_ipos[3 * body], m_.body_ipos[3 * body + 1], m_.body_ipos[3 * body + 2]};
  }

  /// Thrown by step() when SimulationOptions::stop says so.
  struct Stopped {};

  const SimulationOptions& options() const { return plan_.options; }
  int arm() const { return plan_.robot->numArmDofs(); }

  /// Advances the hand's servo targets by one time step of closing: each
  /// towards its closing limit at its joint's speed limit, but never more
  /// than its lead ahead of the joint, so a blocked finger presses with its
  /// effort without its target winding up beyond the contact.
  void advanceHandTarget() {
    for (int i = 0; i < plan_.robot->numHandDofs(); ++i) {
      const double limit = plan_.close_limit(i);
      double& target = hand_target_(i);
      const double step = plan_.robot->maxVelocities()(arm() + i) * options().timestep;
      target += std::clamp(limit - target, -step, step);
      const double q = data_->qpos[plan_.index.dof_qpos[static_cast<std::size_t>(arm() + i)]];
      const double lead = plan_.close_lead(i);
      if (limit > plan_.grasp(arm() + i)) target = std::min(target, q + lead);
      if (limit < plan_.grasp(arm() + i)) target = std::max(target, q - lead);
    }
  }

  bool settleAndClose() {
    for (int s = 0; s < stepsOf(options().settle_time, options().timestep); ++s) {
      step(plan_.pregrasp, "settle");
      if (unstable("settle")) return false;
    }
    const int n = stepsOf(options().close_time, options().timestep);
    Eigen::VectorXd target = plan_.pregrasp;
    hand_target_ = plan_.pregrasp.tail(plan_.robot->numHandDofs());
    for (int s = 1; s <= n; ++s) {
      const double f = static_cast<double>(s) / n;
      target.head(arm()) = (1 - f) * plan_.pregrasp.head(arm()) + f * plan_.grasp.head(arm());
      advanceHandTarget();
      target.tail(plan_.robot->numHandDofs()) = hand_target_;
      step(target, "close");
      if (unstable("close")) return false;
    }
    reference_ = objectInPalm();
    return true;
  }

  bool lift() {
    const int n = stepsOf(plan_.lift_time, options().timestep);
    const auto& waypoints = plan_.lift;
    const double last = static_cast<double>(waypoints.size() - 1);
    for (int s = 1; s <= n; ++s) {
      // Smooth start and stop: s(t) = (1 - cos(pi t / T)) / 2 along the line.
      const double along = last * (1.0 - std::cos(M_PI * s / n)) / 2.0;
      const auto k = static_cast<std::size_t>(std::min(std::floor(along), std::max(0.0, last - 1)));
      const double f = waypoints.size() > 1 ? along - static_cast<double>(k) : 0.0;
      Eigen::VectorXd target =
          (1 - f) * waypoints[k] + f * waypoints[std::min(k + 1, waypoints.size() - 1)];
      target.tail(plan_.robot->numHandDofs()) = hand_target_;
      if (!stepAndTrack(target, "lift")) return false;
    }
    const std::string support = touchedObstacle();
    if (!support.empty())
      return fail("lift: object still touches '" + support + "' after the lift");
    return true;
  }

  /// The configuration the servos hold after the lift.
  Eigen::VectorXd heldTarget() const {
    Eigen::VectorXd target = plan_.lift.back();
    target.tail(plan_.robot->numHandDofs()) = hand_target_;
    return target;
  }

  bool hold() {
    const Eigen::VectorXd target = heldTarget();
    for (int s = 0; s < stepsOf(options().hold_time, options().timestep); ++s)
      if (!stepAndTrack(target, "hold")) return false;
    result_.fingers_in_contact = fingersInContact();
    held_through_hold_ = true;
    return true;
  }

  /// The object's weight along +-x, +-y, +-z in turn, each from the state
  /// at the end of the hold, so one direction's slip does not weaken the next.
  bool disturb() {
    const int n = stepsOf(options().disturbance_time, options().timestep);
    if (n == 0) return true;
    const DataPtr snapshot = makeData(m_);
    mj_copyData(snapshot.get(), &m_, data_.get());
    const Eigen::VectorXd target = heldTarget();
    const double weight = m_.body_mass[plan_.index.object_body] * kGravity;
    const char* names[6] = {"+x", "-x", "+y", "-y", "+z", "-z"};
    for (int k = 0; k < 6; ++k) {
      mj_copyData(data_.get(), &m_, snapshot.get());
      mjtNum* force = data_->xfrc_applied + 6 * plan_.index.object_body;
      force[k / 2] = (k % 2 == 0 ? weight : -weight);
      const std::string phase = std::string("disturbance ") + names[k];
      for (int s = 0; s < n; ++s)
        if (!stepAndTrack(target, phase)) return false;
    }
    return true;
  }

  /// One time step towards `target` (numDofs servo targets): the arm's
  /// servos with gravity compensation (as the arms' own controllers do;
  /// MuJoCo 2.2 has no attribute for it), the hand's without.
  void step(const Eigen::VectorXd& target, const char* phase) {
    if (++steps_ % kStopPollSteps == 0 && options().stop && options().stop()) throw Stopped{};
    mjData& d = *data_;
    for (std::size_t i = 0; i < plan_.index.actuator.size(); ++i)
      d.ctrl[plan_.index.actuator[i]] = target(static_cast<Eigen::Index>(i));
    mj_step1(&m_, &d);
    for (int i = 0; i < arm(); ++i) {
      const int dof = plan_.index.dof_velocity[static_cast<std::size_t>(i)];
      d.qfrc_applied[dof] = d.qfrc_bias[dof];
    }
    mj_step2(&m_, &d);
    elapsed_ += options().timestep;
    record(phase);
  }

  bool stepAndTrack(const Eigen::VectorXd& target, const std::string& phase) {
    step(target, phase.c_str());
    if (unstable(phase)) return false;
    const Eigen::Isometry3d now = objectInPalm();
    const double moved = (now.translation() - reference_.translation()).norm();
    const double turned = Eigen::AngleAxisd(reference_.linear().transpose() * now.linear()).angle();
    result_.max_displacement = std::max(result_.max_displacement, moved);
    result_.max_rotation = std::max(result_.max_rotation, turned);
    if (moved > options().max_displacement)
      return fail(phase + ": object slipped " + millimetres(moved) + " in the palm");
    if (turned > options().max_rotation)
      return fail(phase + ": object turned " + degrees(turned) + " in the palm");
    return true;
  }

  /// MuJoCo resets a diverging simulation and counts it in its warnings;
  /// full contact or constraint buffers drop contacts.
  bool unstable(const std::string& phase) {
    const mjWarningStat* w = data_->warning;
    if (w[mjWARN_BADQACC].number + w[mjWARN_BADQVEL].number + w[mjWARN_BADQPOS].number > 0) {
      fail(phase + ": the simulation diverged");
      return true;
    }
    if (w[mjWARN_CONTACTFULL].number + w[mjWARN_CNSTRFULL].number > 0) {
      fail(phase + ": more contacts than the model has room for");
      return true;
    }
    return false;
  }

  bool fail(const std::string& why) {
    if (result_.failure.empty()) result_.failure = why;
    return false;
  }

  /// The object's centre-of-mass frame in the palm frame.
  Eigen::Isometry3d objectInPalm() const {
    const mjData& d = *data_;
    const int body = plan_.index.object_body;
    Eigen::Isometry3d com = Eigen::Isometry3d::Identity();
    com.translation() << d.xipos[3 * body], d.xipos[3 * body + 1], d.xipos[3 * body + 2];
    com.linear() = bodyPose(d, body).linear();
    return bodyPose(d, plan_.index.palm_body).inverse() * com;
  }

  /// The bodies the object touches now.
  std::set<int> objectContacts() const {
    std::set<int> bodies;
    for (int c = 0; c < data_->ncon; ++c) {
      const int a = m_.geom_bodyid[data_->contact[c].geom1];
      const int b = m_.geom_bodyid[data_->contact[c].geom2];
      if (a == plan_.index.object_body) bodies.insert(b);
      if (b == plan_.index.object_body) bodies.insert(a);
    }
    return bodies;
  }

  /// The name of an obstacle the object touches, or empty.
  std::string touchedObstacle() const {
    for (int c = 0; c < data_->ncon; ++c)
      for (const int g : {data_->contact[c].geom1, data_->contact[c].geom2}) {
        const int other =
            g == data_->contact[c].geom1 ? data_->contact[c].geom2 : data_->contact[c].geom1;
        if (m_.geom_bodyid[g] == 0 && m_.geom_bodyid[other] == plan_.index.object_body) {
          const std::string name = mj_id2name(&m_, mjOBJ_GEOM, g);
          return name.substr(name.find('/') + 1);
        }
      }
    return {};
  }

  int fingersInContact() const {
    const std::set<int> touching = objectContacts();
    int count = 0;
    for (const int body : plan_.index.fingertip_bodies) count += touching.count(body) > 0 ? 1 : 0;
    return count;
  }

  void record(const char* phase) {
    if (motion_ == nullptr || options().record_rate <= 0.0 || elapsed_ + 1e-12 < next_sample_)
      return;
    next_sample_ += 1.0 / options().record_rate;
    motion_->push_back({elapsed_, phase, bodyPose(*data_, plan_.index.object_body),
                        robotConfiguration(*data_, plan_.index)});
  }

  const mjModel& m_;
  const TrialPlan& plan_;
  DataPtr data_;
  std::vector<MotionSample>* motion_;
  Eigen::Isometry3d reference_ = Eigen::Isometry3d::Identity();
  Eigen::VectorXd hand_target_;  ///< the hand servos' targets, held after closing
  TrialResult result_;
  double elapsed_ = 0.0;
  long steps_ = 0;  ///< time steps taken, for polling the stop
  double next_sample_ = 0.0;
  bool held_through_hold_ = false;
  Eigen::Isometry3d released_ = Eigen::Isometry3d::Identity();  ///< the object as the hand opens
  double rest_displacement_ = 0.0;
  double rest_rotation_ = 0.0;
  double stand_displacement_ = 0.0;  ///< in the rest after the retreat
  double stand_rotation_ = 0.0;
  double place_displacement_ = 0.0;
  double place_rotation_ = 0.0;
};

}  // namespace

Eigen::VectorXd closeLimits(const robot::RobotModel& robot, const Eigen::VectorXd& pregrasp,
                            const Eigen::VectorXd& grasp) {
  const int arm = robot.numArmDofs();
  Eigen::VectorXd limits = grasp.tail(robot.numHandDofs());
  for (int i = 0; i < robot.numHandDofs(); ++i) {
    const double closing = grasp(arm + i) - pregrasp(arm + i);
    if (closing > 1e-9) limits(i) = robot.upperLimits()(arm + i);
    if (closing < -1e-9) limits(i) = robot.lowerLimits()(arm + i);
  }
  return limits;
}

Eigen::VectorXd closeLeads(const robot::RobotModel& robot) {
  const robot::HandActuation& hand = *robot.handActuation();
  return kCloseLead * hand.efforts / hand.kp;
}

ModelPtr perturbedModel(const mjModel& nominal, const WorldIndex& index, int numArmDofs,
                        const Perturbation& perturbation) {
  ModelPtr model = copyModel(nominal);
  mjModel& m = *model;
  for (int g = 0; g < m.ngeom; ++g) {
    m.geom_friction[3 * g] *= perturbation.friction_scale;
    m.geom_friction[3 * g + 1] *= perturbation.friction_scale;
  }
  m.body_mass[index.object_body] *= perturbation.mass_scale;
  for (int k = 0; k < 3; ++k) m.body_inertia[3 * index.object_body + k] *= perturbation.mass_scale;
  for (std::size_t d = static_cast<std::size_t>(numArmDofs); d < index.actuator.size(); ++d) {
    const int a = index.actuator[d];
    m.actuator_gainprm[a * mjNGAIN] *= perturbation.gain_scale;
    m.actuator_biasprm[a * mjNBIAS + 1] *= perturbation.gain_scale;
    m.dof_damping[index.dof_velocity[d]] *= perturbation.gain_scale;
  }
  const DataPtr data = makeData(m);
  mj_setConst(&m, data.get());
  return model;
}

TrialResult runTrial(const mjModel& model, const TrialPlan& plan, const std::string& name,
                     std::vector<MotionSample>* motion) {
  return Trial(model, plan, motion).run(name);
}

PlaceVerdict runPlaceTrial(const mjModel& model, const TrialPlan& plan,
                           std::vector<MotionSample>* motion) {
  return Trial(model, plan, motion).runPlace();
}

}  // namespace hfts::physics
