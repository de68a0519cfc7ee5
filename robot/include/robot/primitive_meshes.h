#pragma once
// Triangle meshes of the collision primitives (the tessellation the scene
// and plan exports draw them with), centred at the origin: a box of the
// given size, a cylinder along z, a sphere.

#include <Eigen/Core>

#include "robot/scene.h"

namespace hfts::robot {

using hfts::boxMesh;  // hfts_db/triangle_mesh.h
TriangleMesh cylinderMesh(double radius, double length, int segments = 32);
TriangleMesh sphereMesh(double radius, int segments = 24);

}  // namespace hfts::robot
