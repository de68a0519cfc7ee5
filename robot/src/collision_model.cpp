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

}  // namespace hfts::robot
