#pragma once
// Scenes a sensor saw (docs/point_clouds.md): what of its point-cloud
// obstacles is not an obstacle. A depth camera sees the object to pick and
// the robot itself as well as the world; the planner has models of both,
// so their voxels leave the clouds, as a perception pipeline's self filter
// and segmentation take their points out.

#include <Eigen/Core>

#include "hfts_db/distance_grid.h"
#include "hfts_db/object_database.h"
#include "hfts_db/triangle_mesh.h"
#include "robot/robot_model.h"
#include "robot/scene.h"

namespace hfts::robot {

/// The scene with what its views saw through taken out of its other
/// views: a voxel of one point-cloud obstacle goes when a camera of another
/// (a cloud with a viewpoint: a depth image's) saw a point beyond it along
/// the same ray, and no point of its own lies within its radius. So the
/// shadows one camera leaves behind what it saw (space it cannot know is
/// free) are cleared where another camera looked through them, as
/// occupancy maps fuse views; what a camera saw itself is kept. A scene
/// with fewer than two clouds with viewpoints is returned as it is.
Scene withSeenSpaceCarved(const Scene& scene);

/// The scene with the voxels of its point-cloud obstacles that the target
/// (`vertices` and `grid` in its frame, at scene.target_pose) may touch
/// removed: what a sensor saw of the object to pick, or of its support
/// where the object stands on it, belongs to the object, whose model
/// the planner has. A voxel goes when the grid cannot prove its centre
/// more than half its diagonal outside the object; a cloud left without
/// voxels goes. Obstacles it does not touch are shared, not copied.
Scene withTargetCarved(const Scene& scene, const db::DistanceGrid& grid, const Vertices& vertices);

/// The names of the obstacles withHiddenSide makes for `target`:
/// "<target>.hidden" and "<target>.hidden_skin". The checker does not
/// count them touching the target (CollisionScene::targetTouchesObstacles).
std::string hiddenSideName(const std::string& target);
std::string hiddenSkinName(const std::string& target);
/// Whether `obstacle` names one of them.
bool isHiddenSpaceOf(const std::string& obstacle, const std::string& target);

/// The scene with the space its target's views could not see free (the
/// database's partial_view boxes, target frame, at scene.target_pose) as
/// obstacles: the boxes' voxels (partial_view.hidden_voxel), which no link
/// may touch, so that no finger closes through a side of the object no
/// camera saw. The voxels that may touch the object's solid (as
/// withTargetCarved decides) are their own obstacle, hiddenSkinName: what
/// lies there may be the unseen rest of the object, which goes with it
/// when it is lifted (heldScene); the others are hiddenSideName. The scene
/// as it is for a target without such boxes. Throws InvalidArgument
/// ("partial_view") for boxes whose voxels exceed kMaxCloudVoxels.
Scene withHiddenSide(const Scene& scene, const db::ObjectDatabase& target);

/// The obstacles of `scene` for the robot holding its target: no target,
/// and none of the hidden space touching it (hiddenSkinName), which the
/// object carries with it. What it rests on stays.
Scene heldScene(Scene scene);

/// How far around the robot's links (m) its self filter takes voxels out.
inline constexpr double kSelfFilterPadding = 0.02;

/// The scene with the voxels of its point-cloud obstacles near the robot
/// at `q` (where it stood when the sensor looked: the plan's start)
/// removed: a voxel goes when its centre is within `padding` plus half
/// its diagonal of a link's shape (FCL's distance). A cloud left without
/// voxels goes. Obstacles it does not touch are shared, not copied.
Scene withRobotCarved(const Scene& scene, const RobotModel& model, const Eigen::VectorXd& q,
                      double padding = kSelfFilterPadding);

/// The scene as the planner checks it for `target` (at scene.target_pose)
/// with the robot starting at `start`: withSeenSpaceCarved, withTargetCarved,
/// withHiddenSide (for an object from views), withRobotCarved, in that
/// order.
Scene asPlannerSees(const Scene& scene, const db::ObjectDatabase& target, const RobotModel& model,
                    const Eigen::VectorXd& start);

}  // namespace hfts::robot
