#pragma once
// A planned grasp as an animated binary glTF (docs/trajectories.md): the
// scene, the object, the robot with one node per link moving along the
// trajectory, the contacts as small markers with their normals, and the
// path the palm takes as a line. Any glTF viewer plays it.

#include <Eigen/Geometry>

#include <filesystem>
#include <string>
#include <vector>

#include "hfts_db/object_database.h"
#include "robot/robot_model.h"
#include "robot/scene.h"

namespace hfts::robot {

/// What is shown besides the scene.
struct PlanAnimation {
  std::vector<double> times;                                      ///< s from 0, increasing
  std::vector<Eigen::VectorXd> configurations;                    ///< one per time
  Eigen::Isometry3d object_pose = Eigen::Isometry3d::Identity();  ///< the target, world frame
  Eigen::Matrix3Xd contacts, inward_normals;  ///< world frame, one column per contact
  std::vector<Eigen::VectorXd> path;          ///< the planned path (drawn through the palm)
  /// The object's pose (world frame) at each of `times` when the plan
  /// moves it (the hand carries it after the grasp); empty: it stands at
  /// object_pose throughout.
  std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>> object_motion;
  /// A simulated motion of the grasp (the physics check's nominal trial:
  /// close, lift, hold, disturbances), shown as a second animation: robot
  /// configurations and the object's pose (world frame) at
  /// `simulated_times`, s from 0. Empty: none.
  std::vector<double> simulated_times;
  std::vector<Eigen::VectorXd> simulated_configurations;
  std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>> simulated_object;
};

/// The .glb bytes (assimp's glTF 2 exporter; world frame turned to glTF's
/// y up, metres). One animation, "plan", with a translation and a
/// rotation channel per link node, keyed at `times`, and one for the
/// object's node when the plan moves it (object_motion); with a simulated
/// motion a second one, "simulated", whose channels move the links and
/// the object's node too (and "plan" then keeps the object still, or moves
/// it as object_motion says, with a channel of its own, so that either can
/// be played after the other).
/// Throws InvalidArgument naming the field: times and configurations of
/// different lengths, empty, not increasing or not finite, a configuration
/// of the wrong size, contacts and normals of different shapes, object
/// poses ("object_motion") not one per time or not finite, likewise for
/// the simulated times, configurations and object poses.
std::string planGlb(const RobotModel& model, const Scene& scene, const db::ObjectGeometry* target,
                    const PlanAnimation& plan);

/// planGlb written to `path` (atomically); InvalidArgument ("path") unless
/// it ends in .glb.
void exportPlanGlb(const RobotModel& model, const Scene& scene, const db::ObjectGeometry* target,
                   const PlanAnimation& plan, const std::filesystem::path& path);

}  // namespace hfts::robot
