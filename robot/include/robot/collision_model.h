#pragma once
// What collision checking derives from a robot (docs/collision.md): the
// conservative sphere model of its links (link_spheres.h) and the maps of
// where link pairs are apart in joint space (pair_maps.h). The kinematic
// RobotModel knows nothing of them: buildCollisionModel derives them once,
// and the result is read-only, shared by every scene, checker and thread
// that checks the robot (a CollisionScene places it in a scene, a
// CollisionChecker is one thread's working state over that scene).

#include <memory>
#include <string>
#include <vector>

#include "robot/link_spheres.h"
#include "robot/pair_maps.h"
#include "robot/robot_model.h"

namespace hfts::robot {

struct CollisionModelOptions {
  SphereModelOptions spheres;
  PairMapOptions pair_maps;
};

/// A robot with its derived collision data. Immutable once built.
struct CollisionModel {
  RobotModel robot;
  SphereModel spheres;
  std::vector<PairMap> pair_maps;
};

/// The model of `model`'s robot holding a rigid body (a grasped object):
/// the robot RobotModel::withHeldBody makes, its new link covered with
/// spheres of `spheres`' tolerance (the surface, as FCL checks a mesh), the
/// pair maps of `model` (the new link has none: it is always tested).
/// Throws InvalidArgument as withHeldBody.
std::shared_ptr<const CollisionModel> withHeldBody(const CollisionModel& model,
                                                   const std::string& name,
                                                   const Eigen::Isometry3d& inPalm,
                                                   std::shared_ptr<const TriangleMesh> mesh,
                                                   const SphereModelOptions& spheres = {});

/// Covers the robot's links with spheres and builds its pair maps (about
/// 0.5 s for the KR5 + SDH). Deterministic. Throws std::invalid_argument
/// for options buildSphereModel rejects.
std::shared_ptr<const CollisionModel> buildCollisionModel(
    RobotModel robot, const CollisionModelOptions& options = {});

}  // namespace hfts::robot
