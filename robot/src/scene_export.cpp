// assimp scene construction and glTF export.
#include "robot/scene_export.h"

#include <cmath>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/invalid_argument.h"
#include "robot/kinematics.h"

#include "glb_builder.h"
#include "robot/primitive_meshes.h"

namespace hfts::robot {
namespace {

using namespace glb;

std::vector<Part> robotParts(const RobotModel& model, const Scene& scene,
                             const Eigen::VectorXd& q) {
  const LinkPoses poses = forwardKinematics(model, q);
  std::vector<Part> parts;
  for (std::size_t l = 0; l < model.links().size(); ++l) {
    const Link& link = model.links()[l];
    const unsigned colour = linkMaterial(model, l);
    for (std::size_t s = 0; s < link.shapes.size(); ++s) {
      const CollisionShape& shape = link.shapes[s];
      parts.push_back({transformed(primitiveMesh(static_cast<int>(shape.type), shape.size),
                                   scene.robot_base * poses[l] * shape.origin),
                       colour, link.name + "_" + std::to_string(s)});
    }
  }
  // The fingertip contact points as small spheres, to check the pads.
  const FingertipFrames tips = fingertipFrames(model, poses);
  for (Eigen::Index i = 0; i < tips.positions.cols(); ++i) {
    const Eigen::Isometry3d at(
        Eigen::Translation3d(scene.robot_base * Eigen::Vector3d(tips.positions.col(i))));
    parts.push_back(
        {transformed(sphereMesh(0.005, 12), at), kTarget, "contact_" + std::to_string(i)});
  }
  return parts;
}

}  // namespace

void exportSceneGlb(const RobotModel& model, const Scene& scene, const db::ObjectGeometry* target,
                    const Eigen::VectorXd& q, const std::filesystem::path& path) {
  if (q.size() != model.numDofs())
    throw InvalidArgument("configuration", std::to_string(model.numDofs()) +
                                               " values expected, got " + std::to_string(q.size()));
  if (path.extension() != ".glb")
    throw InvalidArgument("path", "'" + path.string() + "' must end in .glb (binary glTF)");
  std::vector<Part> parts = robotParts(model, scene, q);
  for (Part& p : environmentParts(scene, target,
                                  target != nullptr ? targetPose(scene, target->mesh_vertices)
                                                    : Eigen::Isometry3d::Identity()))
    parts.push_back(std::move(p));
  // One named node per part, so viewers list links and obstacles by name.
  Builder builder;
  for (const Part& part : parts) builder.addNode(part.name, {part});
  addSensedPoints(builder, scene);
  core::writeFileAtomically(path, builder.glb("'" + path.string() + "'"));
}

}  // namespace hfts::robot
