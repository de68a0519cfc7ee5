#include "robot/collision_model.h"

#include <utility>

namespace hfts::robot {

std::shared_ptr<const CollisionModel> buildCollisionModel(RobotModel robot,
                                                          const CollisionModelOptions& options) {
  auto model = std::make_shared<CollisionModel>(CollisionModel{std::move(robot), {}, {}});
  model->spheres = buildSphereModel(model->robot, options.spheres);
  model->pair_maps = buildPairMaps(model->robot, model->spheres, options.pair_maps);
  return model;
}

std::shared_ptr<const CollisionModel> withHeldBody(const CollisionModel& model,
                                                   const std::string& name,
                                                   const Eigen::Isometry3d& inPalm,
                                                   std::shared_ptr<const TriangleMesh> mesh,
                                                   const SphereModelOptions& spheres) {
  auto held = std::make_shared<CollisionModel>(CollisionModel{
      model.robot.withHeldBody(name, inPalm, std::move(mesh)), model.spheres, model.pair_maps});
  held->spheres.links.push_back(coverLink(held->robot.links().back(), spheres));
  return held;
}

}  // namespace hfts::robot
