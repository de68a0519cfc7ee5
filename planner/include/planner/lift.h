#pragma once
// After the grasp, the object moves with the hand (docs/placement.md): the
// robot holding it (robot::withHeldBody, both collision tiers) and the
// lift that takes it clear of its support, a straight line of the palm
// checked with the object in the hand.

#include <Eigen/Geometry>

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hfts_db/object_database.h"
#include "planner/grasp_trajectory.h"
#include "planner/motion_check.h"
#include "planner/planning_world.h"
#include "robot/collision_checker.h"
#include "robot/collision_model.h"
#include "robot/scene.h"

namespace hfts::planner {

/// The lift a plan ends with unless the request turns it off.
struct LiftOptions {
  double height = 0.10;  ///< how far the palm lifts the object (m, in (0, 1])
  /// How fast the arm moves while the hand holds the object (the lift, the
  /// carry, the descent of a pick and place): the fraction of the robot's
  /// velocity limits, its square of the acceleration limits (the same
  /// motion, 1 / held_speed times slower), in (0, 1]. 0.5 lost the
  /// object from the hand less often in the pick and place benchmark
  /// (docs/experiments/2026-12-07-held-speed.md).
  double held_speed = 0.5;
};

/// Checks the options (InvalidArgument "lift.height", "lift.held_speed").
void checkLiftOptions(const LiftOptions& options);

/// The robot holding an object as the hand closed on it.
struct Hold {
  /// The robot with the object as a link fixed to its palm.
  std::shared_ptr<const robot::CollisionModel> model;
  Eigen::Isometry3d object_in_palm = Eigen::Isometry3d::Identity();
};

/// The robot of `model` at `grasp` (a full configuration, base at
/// `robotBase`) holding `object` (named `name`), which stands at
/// `objectPose` (world): it moves with the palm from now on.
Hold holdObject(const robot::CollisionModel& model, const Eigen::Isometry3d& robotBase,
                const db::ObjectGeometry& object, const std::string& name,
                const Eigen::Isometry3d& objectPose, const Eigen::VectorXd& grasp);

/// The world of the robot holding the object, its hand fixed as it closed
/// at `grasp` (RobotModel::withHandFixed): motion plans in it carry the
/// object, moving the arm only (PlanningWorld's motion-only world, the
/// objects of `world`).
std::shared_ptr<const PlanningWorld> carryWorld(const PlanningWorld& world, const Hold& hold,
                                                const Eigen::VectorXd& grasp);

/// A lift: the palm on straight lines with its orientation kept, the hand
/// as closed; or a planned motion when no such lines are free.
struct LiftPath {
  /// The grasp first; along straight lines one configuration per 5 mm of
  /// palm travel, along a planned motion no joint moving more than 0.01
  /// rad between two.
  std::vector<Eigen::VectorXd> path;
  /// One straight line: "up" (world z), "up_retreat" (45 degrees between
  /// up and back along the palm's approach axis), "retreat" (back along
  /// it), "up_to_base" (45 degrees between up and towards the robot's
  /// base), "up_x", "up_minus_x", "up_y" or "up_minus_y" (45 degrees
  /// between up and the world's axis): the first of these that is free and
  /// within 60 degrees of up (a lift raises the object by at least half its
  /// height).
  /// Out from under something: 1 cm up, then 0.1, 0.2 or 0.3 m
  /// horizontally, then up the rest of the height: "out_to_base",
  /// "out_back" (the approach axis's horizontal part, backwards), "out_x",
  /// "out_minus_x", "out_y", "out_minus_y".
  /// "planned": a motion planned for the robot holding the object
  /// (docs/placement.md "The lift").
  std::string direction;
};

/// The first lift of `height` from `grasp` (LiftPath::direction's order:
/// the straight ones, then out from under something) whose lines the palm
/// can follow within the joint limits and that `check` finds free
/// (robot::CertifyRule::kTransit) for the robot holding the object in
/// `scene` (its obstacles; its target is ignored: the object is in the
/// hand). None when every one is blocked (`why` then names what blocked
/// "up"), or when `stop` returns true (polled between lines and within
/// proofs); the planner then plans one. `queries` gets the proofs'
/// distance queries.
std::optional<LiftPath> planLift(const Hold& hold, const robot::Scene& scene,
                                 const Eigen::VectorXd& grasp, double height,
                                 const MotionCheck& check, std::string* why = nullptr,
                                 std::size_t* queries = nullptr,
                                 const std::function<bool()>& stop = {});

/// A straight line of the palm (orientation kept) of the robot holding the
/// object, from `from` by `distance` along `direction` (world): the lift's
/// check (planLift) for any direction, e.g. the descent onto a support.
/// None when the palm cannot follow it within the joint limits or it is
/// not free (`why` then says what stops it) or `stop` returned true.
std::optional<std::vector<Eigen::VectorXd>> heldPalmLine(
    const Hold& hold, const robot::Scene& scene, const Eigen::VectorXd& from,
    const Eigen::Vector3d& direction, double distance, const MotionCheck& check,
    std::string* why = nullptr, std::size_t* queries = nullptr,
    const std::function<bool()>& stop = {});

/// The lift as a trajectory (motionTrajectory of its path for the robot
/// holding the object in `scene`, at `speed`), sampled at `rate`; empty
/// points when its samples cannot be made free. Throws as motionTrajectory.
GraspTrajectory liftTrajectory(const Hold& hold, const robot::Scene& scene, const LiftPath& lift,
                               const MotionCheck& check, double rate,
                               std::size_t* queries = nullptr, double speed = 1.0);

}  // namespace hfts::planner
