#include "robot_check.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <utility>

#include "grasp/hand_map_builder.h"
#include "robot/arm_ik.h"
#include "robot/collision_checker.h"
#include "robot/collision_model.h"
#include "robot/hand_chain.h"
#include "robot/kinematics.h"
#include "robot/robot_model.h"

namespace hfts::preprocess {
namespace {

using Level = RobotFinding::Level;

/// Random configurations for the sampling checks: the same on every run.
constexpr std::uint64_t kSeed = 1;
constexpr int kIkPoses = 50;
constexpr int kCollisionPostures = 300;
/// A pair colliding in more of the random postures than this is suspect.
constexpr double kSuspectPairShare = 0.5;

std::string percent(double share) {
  std::ostringstream out;
  out.precision(share < 0.01 ? 2 : 3);
  out << 100.0 * share << " %";
  return out.str();
}

std::string millimetres(double metres) {
  std::ostringstream out;
  out.precision(3);
  out << 1000.0 * metres << " mm";
  return out.str();
}

class RobotChecker {
 public:
  explicit RobotChecker(const robot::RobotModel& model) : model_(model), rng_(kSeed) {}

  std::vector<RobotFinding> run() {
    add(Level::kOk, "model",
        "'" + model_.name() + "': " + std::to_string(model_.numDofs()) + " DoF (" +
            std::to_string(model_.numArmDofs()) + " arm, " + std::to_string(model_.numHandDofs()) +
            " hand), " + std::to_string(model_.links().size()) + " links, " +
            std::to_string(model_.fingertips().size()) + " fingertips");
    checkHand();
    checkContactModel();
    checkArmIk();
    checkSpheres();
    if (collision_) {
      checkPosture("home", model_.home());
      Eigen::VectorXd open = model_.home();
      open.tail(model_.numHandDofs()) = model_.handOpen();
      checkPosture("hand_open", open);
      checkRandomPostures();
    } else {
      add(Level::kError, "self collisions",
          "not checked: the collision model could not be built (see spheres)");
    }
    checkLimits();
    return std::move(findings_);
  }

 private:
  void add(Level level, const std::string& topic, const std::string& message) {
    findings_.push_back({level, topic, message});
  }

  Eigen::VectorXd randomConfiguration() {
    Eigen::VectorXd q(model_.numDofs());
    for (Eigen::Index d = 0; d < q.size(); ++d)
      q(d) = std::uniform_real_distribution<double>(model_.lowerLimits()(d),
                                                    model_.upperLimits()(d))(rng_);
    return q;
  }

  void checkHand() {
    const auto m = static_cast<int>(model_.fingertips().size());
    if (m < robot::hand::kMinFingers || m > robot::hand::kMaxFingers) {
      add(Level::kError, "fingertips",
          "the hand map needs " + std::to_string(robot::hand::kMinFingers) + " to " +
              std::to_string(robot::hand::kMaxFingers) +
              " fingertips (the m of the m-contact HFTS); the config lists " + std::to_string(m));
      return;
    }
    grasp::HandMapOptions options = grasp::handMapOptions(model_);
    options.num_samples = 200;
    options.max_draws = 200000;
    try {
      const db::HandMap map = grasp::buildHandMap(model_, options);
      const double share =
          static_cast<double>(map.numSamples()) / static_cast<double>(map.num_draws);
      const std::string counts = std::to_string(map.numSamples()) + " of " +
                                 std::to_string(map.num_draws) + " random hand postures (" +
                                 percent(share) + ") are grasp postures";
      if (map.numSamples() < options.num_samples || share < 0.001)
        add(Level::kWarning, "hand",
            "only " + counts +
                ": building the hand map will take long and cover little; check each "
                "fingertip's `point` (on the pad) and `normal` (out of the pad, towards the "
                "object) and the hand joint limits");
      else
        add(Level::kOk, "hand", counts + "; the hand map uses m = " + std::to_string(m));
    } catch (const robot::ModelError& e) {
      add(Level::kError, "hand",
          std::string(e.what()) +
              " (a grasp posture has fingertips at least 1 cm apart with the pads facing each "
              "other: check each fingertip's `point` and `normal`, which points out of the pad)");
    }
  }

  void checkContactModel() {
    const double gamma = model_.torsionalFriction();
    if (gamma > 0) {
      add(Level::kOk, "contact_model",
          "soft fingers, torsional friction " + millimetres(gamma) + " per unit normal force");
      return;
    }
    if (model_.fingertips().size() == 2)
      add(Level::kWarning, "contact_model",
          "two hard fingertips cannot resist a torque about the line through them, so every "
          "grasp has epsilon 0: set \"contact_model\": \"soft_finger\" and "
          "\"torsional_friction\" (docs/grasp_quality.md)");
    else
      add(Level::kOk, "contact_model", "hard fingers (point contacts with friction)");
  }

  void checkArmIk() {
    std::optional<robot::ArmIk> ik;
    try {
      ik.emplace(model_);
    } catch (const robot::ModelError& e) {
      add(Level::kError, "arm IK", e.what());
      return;
    }
    int solved = 0;
    std::mt19937_64 ikRng(kSeed);
    for (int i = 0; i < kIkPoses; ++i) {
      const Eigen::VectorXd arm = randomConfiguration().head(model_.numArmDofs());
      if (!ik->solveFlange(ik->flangePose(arm), ikRng).empty()) ++solved;
    }
    const std::string method = ik->form() == robot::ArmIk::Form::kSphericalWrist
                                   ? "closed form (spherical wrist)"
                               : ik->form() == robot::ArmIk::Form::kThreeParallel
                                   ? "closed form (three parallel axes, UR type)"
                                   : "numerical (damped least squares)";
    const std::string result = method + ", " + std::to_string(solved) + " of " +
                               std::to_string(kIkPoses) + " random reachable poses solved";
    if (solved < kIkPoses * 9 / 10)
      add(Level::kWarning, "arm IK",
          result +
              ": goal sampling will miss grasps; check arm_joints, the joint limits and "
              "flange_link");
    else
      add(Level::kOk, "arm IK", result);
  }

  void checkPosture(const std::string& name, const Eigen::VectorXd& q) {
    robot::CollisionChecker checker(*collision_, robot::Scene{}, nullptr);
    robot::CollisionPair pair;
    if (checker.inCollision(q, &pair))
      add(Level::kError, name,
          "links '" + pair.first + "' and '" + pair.second +
              "' collide: if they overlap by construction (neighbours at a joint), add [\"" +
              pair.first + "\", \"" + pair.second + "\"] to disabled_collisions; else change " +
              name);
    else
      add(Level::kOk, name, "free of self collisions");
  }

  void checkRandomPostures() {
    robot::CollisionChecker checker(*collision_, robot::Scene{}, nullptr);
    std::map<std::pair<std::string, std::string>, int> pairs;
    int colliding = 0;
    for (int i = 0; i < kCollisionPostures; ++i) {
      robot::CollisionPair pair;
      if (!checker.inCollision(randomConfiguration(), &pair)) continue;
      ++colliding;
      ++pairs[std::minmax(pair.first, pair.second)];
    }
    const double share = static_cast<double>(colliding) / kCollisionPostures;
    bool suspect = false;
    for (const auto& [pair, count] : pairs) {
      const double pairShare = static_cast<double>(count) / kCollisionPostures;
      if (pairShare <= kSuspectPairShare) continue;
      suspect = true;
      add(Level::kWarning, "disabled_collisions",
          "links '" + pair.first + "' and '" + pair.second + "' collide in " + percent(pairShare) +
              " of random postures: if they overlap by construction, add them to "
              "disabled_collisions");
    }
    if (!suspect)
      add(colliding == kCollisionPostures ? Level::kError : Level::kOk, "self collisions",
          percent(share) + " of " + std::to_string(kCollisionPostures) +
              " random postures collide with the robot itself");
  }

  /// Builds the collision model the posture checks use.
  void checkSpheres() {
    try {
      collision_ = robot::buildCollisionModel(model_);
      const robot::SphereModel& spheres = collision_->spheres;
      add(Level::kOk, "spheres",
          std::to_string(spheres.numSpheres()) + " spheres cover the links, at most " +
              millimetres(spheres.maxExcess()) + " beyond them");
    } catch (const std::exception& e) {
      add(Level::kError, "spheres", e.what());
    }
  }

  void checkLimits() {
    if (model_.maxAccelerations().size() == 0)
      add(Level::kWarning, "max_accelerations",
          "missing: plans get no time-parameterised trajectory (docs/trajectories.md)");
    else
      add(Level::kOk, "max_accelerations", "present (trajectories can be timed)");
  }

  const robot::RobotModel& model_;
  std::shared_ptr<const robot::CollisionModel> collision_;  ///< null until built, or when it failed
  std::mt19937_64 rng_;
  std::vector<RobotFinding> findings_;
};

}  // namespace

std::vector<RobotFinding> checkRobot(const std::filesystem::path& config) {
  std::optional<robot::RobotModel> model;
  try {
    model.emplace(robot::RobotModel::load(config));
  } catch (const robot::ModelError& e) {
    return {{Level::kError, "config", e.what()}};
  }
  return RobotChecker(*model).run();
}

int printRobotFindings(const std::vector<RobotFinding>& findings, std::ostream& out) {
  bool error = false;
  for (const RobotFinding& f : findings) {
    const char* level = f.level == Level::kOk        ? "ok     "
                        : f.level == Level::kWarning ? "warning"
                                                     : "error  ";
    out << level << "  " << f.topic << ": " << f.message << "\n";
    error = error || f.level == Level::kError;
  }
  out << (error ? "the robot is not ready for planning: fix the errors above\n"
                : "the robot is ready for planning\n");
  return error ? 1 : 0;
}

}  // namespace hfts::preprocess
