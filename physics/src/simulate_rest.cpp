// simulateRest: the object alone on its support in MuJoCo.
#include "physics/simulate_rest.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "core/invalid_argument.h"
#include "mujoco_world.h"
#include "physics/mjcf_scene.h"
#include "physics/object_body.h"

namespace hfts::physics {
namespace {}  // namespace

void validateRestOptions(const RestOptions& o) {
  const auto positive = [](double value, const char* field) {
    if (!(std::isfinite(value) && value > 0.0))
      throw InvalidArgument(std::string("options.") + field, "must be a finite number > 0");
  };
  if (o.density) positive(*o.density, "density");
  if (!(std::isfinite(o.friction) && o.friction >= 0.0))
    throw InvalidArgument("options.friction", "must be a finite number >= 0");
  positive(o.duration, "duration");
  positive(o.max_displacement, "max_displacement");
  positive(o.max_rotation, "max_rotation");
  if (!(o.timestep > 0.0 && o.timestep <= 0.005))
    throw InvalidArgument("options.timestep", "must be in (0, 0.005] s");
}

namespace {

std::string beyond(const char* what, double amount, const char* unit, double time) {
  char text[96];
  std::snprintf(text, sizeof text, "%s %.1f %s by %.2f s", what, amount, unit, time);
  return text;
}

}  // namespace

RestVerdict simulateRest(const robot::Scene& scene, const db::ObjectDatabase& object,
                         const Eigen::Isometry3d& pose, const RestOptions& options) {
  validateRestOptions(options);
  if (!pose.matrix().allFinite()) throw InvalidArgument("pose", "must be finite");
  ObjectBody body{collisionPieces(object),
                  objectMassProperties(object, objectDensity(object, options.density)), pose};
  ModelSettings settings;
  settings.timestep = options.timestep;
  settings.friction = options.friction;
  const ModelPtr model = compileMjcf(mjcfObjectScene(scene, body, settings));
  const DataPtr data = makeData(*model);
  const int bodyId = mj_name2id(model.get(), mjOBJ_BODY, kObjectBodyName);
  const int joint = mj_name2id(model.get(), mjOBJ_JOINT, kObjectBodyName);
  const int qpos = model->jnt_qposadr[joint];
  const Eigen::Quaterniond q0(pose.linear());
  for (int i = 0; i < 3; ++i) data->qpos[qpos + i] = pose.translation()(i);
  data->qpos[qpos + 3] = q0.w();
  data->qpos[qpos + 4] = q0.x();
  data->qpos[qpos + 5] = q0.y();
  data->qpos[qpos + 6] = q0.z();
  mj_forward(model.get(), data.get());
  const Eigen::Vector3d com0 = pose * body.mass.center_of_mass;

  RestVerdict verdict;
  const auto steps = static_cast<long>(std::ceil(options.duration / options.timestep));
  for (long s = 0; s < steps; ++s) {
    mj_step(model.get(), data.get());
    const Eigen::Isometry3d now = bodyPose(*data, bodyId);
    const double moved = (now * body.mass.center_of_mass - com0).norm();
    const double turned = Eigen::AngleAxisd(pose.linear().transpose() * now.linear()).angle();
    verdict.displacement = std::max(verdict.displacement, moved);
    verdict.rotation = std::max(verdict.rotation, turned);
    if (verdict.failure.empty() && moved > options.max_displacement)
      verdict.failure = beyond("moved", 1000.0 * moved, "mm", data->time);
    if (verdict.failure.empty() && turned > options.max_rotation)
      verdict.failure = beyond("turned", turned * 180.0 / M_PI, "degrees", data->time);
  }
  verdict.stable = verdict.failure.empty();
  return verdict;
}

}  // namespace hfts::physics
