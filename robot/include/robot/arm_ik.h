#pragma once
// Inverse kinematics of the arm for a desired flange (or palm) pose.

#include <Eigen/Geometry>

#include <memory>
#include <random>
#include <vector>

#include "robot/robot_model.h"

namespace hfts::robot {

struct IkOptions {
  double tolerance = 1e-9;  ///< accepted position (m) / orientation (rad) error
  /// Numerical solver (and fallback): attempts from random seeds.
  int restarts = 30;
  int iterations = 200;
  double damping = 0.05;
};

/// All arm configurations that put the flange at a pose, within the joint
/// limits. Uses a closed form when the arm has 6 DoF and either a spherical
/// wrist on a planar shoulder-elbow chain (such as the KR5: axis 1
/// vertical, axes 2 and 3 parallel, axes 4-6 meeting in one point; up to 8
/// solutions) or three parallel middle axes (the UR type: axes 2-4
/// parallel, axes 1 and 5 perpendicular to them, axes 5 and 6 meeting in
/// one point; up to 8 solutions); otherwise damped least squares from random seeds
/// (IkOptions::restarts of them). A redundant arm (more than 6 DoF, e.g. the Panda's 7) has a
/// continuum of solutions: the numerical solver returns those its seeds
/// reach, at least 0.1 rad apart in some joint. Every returned solution is
/// verified by forward kinematics.
class ArmIk {
 public:
  /// Throws ModelError if the arm is not a chain of at least 6 revolute
  /// joints from the base to the flange link, or the palm is not rigidly
  /// fixed to it.
  explicit ArmIk(const RobotModel& model);
  ~ArmIk();
  ArmIk(ArmIk&&) noexcept;

  /// How poses are solved, selected from the geometry at construction.
  enum class Form { kNumerical, kSphericalWrist, kThreeParallel };
  Form form() const;
  /// True when a closed form applies.
  bool isAnalytic() const;

  /// All arm solutions (numArmDofs() values each; extra turns of joints whose range
  /// exceeds a full turn are separate solutions) for a flange pose in the
  /// base frame. `rng` seeds the numerical solver (unused by the closed form).
  std::vector<Eigen::VectorXd> solveFlange(const Eigen::Isometry3d& flange,
                                           std::mt19937_64& rng) const;
  /// The same for a palm pose (the palm is rigidly fixed to the flange).
  std::vector<Eigen::VectorXd> solvePalm(const Eigen::Isometry3d& palm, std::mt19937_64& rng) const;

  /// Damped-least-squares IK from random seeds; distinct solutions found.
  std::vector<Eigen::VectorXd> solveNumerically(const Eigen::Isometry3d& flange,
                                                std::mt19937_64& rng) const;

  /// Flange pose of arm configuration `arm` (numArmDofs() values).
  Eigen::Isometry3d flangePose(const Eigen::VectorXd& arm) const;
  /// The palm in the flange frame.
  const Eigen::Isometry3d& palmInFlange() const;

  IkOptions& options();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// True when two arm configurations of the same size differ by whole turns
/// of their joints only (each difference within `tolerance` rad of a
/// multiple of 2 pi). ArmIk's arm joints are all revolute, so such
/// solutions put every link in the same place: the same collisions, the
/// same fingertips (solveFlange returns them as separate solutions).
bool differByWholeTurns(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                        double tolerance = 1e-9);

/// Of each class of `solutions` that differ by whole turns only, the one
/// variant nearest `reference` joint by joint within [lower, upper] (so
/// also in any weighted joint metric), once. Each solution is moved to
/// that variant; one that already was it keeps its place in the order, a
/// moved one is kept only when its class had no such solution (a
/// numerical solver need not have found it; a closed form lists every
/// variant). Ties keep the solution's own value. All vectors of one size.
std::vector<Eigen::VectorXd> nearestWholeTurns(const std::vector<Eigen::VectorXd>& solutions,
                                               const Eigen::VectorXd& reference,
                                               const Eigen::VectorXd& lower,
                                               const Eigen::VectorXd& upper);

}  // namespace hfts::robot
