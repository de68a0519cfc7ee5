#pragma once
// Exporting a scene with the robot in a configuration as glTF, so a person
// can look at it in any viewer.

#include <Eigen/Core>

#include <filesystem>

#include "hfts_db/object_database.h"
#include "robot/robot_model.h"
#include "robot/scene.h"

namespace hfts::robot {

/// Writes the robot at configuration q (collision primitives, tessellated),
/// the obstacles and the target object (if not null; where targetPose()
/// puts it) as a binary glTF (.glb, assimp's glTF 2 exporter), world frame,
/// metres, z up as in the scene. Written atomically. Throws InvalidArgument
/// for a q of the wrong size or a path not ending in .glb, SceneError for a
/// rest_on naming no obstacle, std::runtime_error if assimp fails.
void exportSceneGlb(const RobotModel& model, const Scene& scene, const db::ObjectGeometry* target,
                    const Eigen::VectorXd& q, const std::filesystem::path& path);

}  // namespace hfts::robot
