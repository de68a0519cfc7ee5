#pragma once
// Does a plan's grasp hold? The checks that make a goal
// (docs/planning.md#what-a-goal-is), made again on any plan's pre-grasp and
// grasp, and the physics check (physics/simulate_grasp.h): what
// hfts-validate, the service's `validate` and hfts-bench ask of a plan.

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

#include "physics/simulate_grasp.h"
#include "planner/goal_sampler.h"
#include "planner/planning_world.h"
#include "robot/collision_checker.h"
#include "robot/scene.h"

namespace hfts::planner {

/// What a grasp must meet; the planner parameters of the same names.
struct GraspCheckOptions {
  double min_epsilon = kDefaultMinEpsilon;
  double max_penetration = robot::kDefaultMaxPenetration;
  /// Resolution (Eq. (3) metric) at which the closing motion is checked:
  /// the planner's final_resolution.
  double resolution = 0.0025;
  double friction = 0.5;  ///< mu of the epsilon (the planner's "friction")
};

/// The geometric checks of a grasp: the hand closed again from the
/// pre-grasp (the arm where the pre-grasp has it, the fingers along the
/// line towards the grasp, continued to contact) is the grasp as executed.
struct GraspCheck {
  /// Every fingertip's pad touches the object when the hand closes.
  bool pads_touch = false;
  /// Largest difference (rad, or m for a sliding joint) between the hand
  /// of the given grasp and the executed one: 0 for a grasp the planner
  /// made; a fingertip left short makes it positive.
  double closing_difference = 0.0;
  Eigen::VectorXd executed;  ///< the executed grasp (full configuration)
  /// Ferrari-Canny epsilon at the contacts the executed grasp touches (0
  /// unless every pad touches).
  double epsilon = 0.0;
  double penetration = 0.0;  ///< deepest fingertip link inside the object (m)
  /// grasp::loadCapacity of the executed grasp with the hand's rated
  /// efforts and the object's mass (its density as the physics check
  /// takes it): below 1 the hand cannot hold the object's weight and the
  /// check's disturbances, whatever its servos do. Unset without
  /// hand_actuation or when not every pad touches.
  std::optional<double> load_capacity;
  /// The pre-grasp is free under the full rule, the executed grasp and the
  /// closing motion under the grasp rule (max_penetration).
  bool clear = false;
  /// The first criterion not met, in words (empty when all are met).
  std::string problem;
  bool valid() const { return problem.empty(); }
};

struct ValidationRequest {
  /// The scene with the object where the plan had it: target_object names
  /// its database, target_pose is its pose.
  robot::Scene scene;
  Eigen::VectorXd pregrasp;  ///< the path's last but one configuration
  Eigen::VectorXd grasp;     ///< the path's last configuration
  GraspCheckOptions check;
  /// Also simulate the executed grasp (physics::simulateGrasp).
  bool physics = true;
  /// The lift the simulation follows (a plan's, from the grasp on); empty:
  /// the one the physics protocol plans.
  std::vector<Eigen::VectorXd> lift;
  physics::SimulationOptions simulation;
};

struct Validation {
  GraspCheck check;
  std::optional<physics::GraspVerdict> physics;  ///< with ValidationRequest::physics
  /// A pick and place's: the plan simulated from the closing to the
  /// object at rest where it was put (physics::simulatePickAndPlace).
  std::optional<physics::PlaceVerdict> place;
  /// The checks are met and, where it ran, the physics check held.
  bool holds() const { return check.valid() && (!physics || physics->held); }
};

/// Checks a grasp. Throws InvalidArgument naming the field for a
/// configuration of the wrong size, not finite or outside the joint
/// limits ("pregrasp", "grasp"), an unknown object ("scene.target_object")
/// or bad options ("check.*", "options.*").
Validation validateGrasp(const PlanningWorld& world, const ValidationRequest& request);

}  // namespace hfts::planner
