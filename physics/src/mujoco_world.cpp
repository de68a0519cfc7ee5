// MuJoCo models and data as owned objects; the parts of a compiled scene.
#include "mujoco_world.h"

#include <array>
#include <cstring>
#include <mutex>
#include <stdexcept>

#include "contact_filter.h"
#include "physics/mjcf_scene.h"

namespace hfts::physics {
namespace {

void throwError(const char* message) {
  throw SimulationError(std::string("MuJoCo: ") + message);
}

void ignoreWarning(const char* /*message*/) {}

int findId(const mjModel& model, mjtObj type, const std::string& name) {
  const int id = mj_name2id(&model, type, name.c_str());
  if (id < 0) throw std::logic_error("the MuJoCo model has no '" + name + "'");
  return id;
}

}  // namespace

void installMujocoHandlers() {
  static std::once_flag installed;
  std::call_once(installed, [] {
    mju_user_error = throwError;
    mju_user_warning = ignoreWarning;
    mjcb_contactfilter = filterContactPair;
  });
}

ModelPtr compileMjcf(const std::string& xml) {
  installMujocoHandlers();
  static std::mutex compiler;
  const std::lock_guard<std::mutex> lock(compiler);
  // About 2 MB of file names: on the heap.
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const char* file = "scene.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), file, static_cast<int>(xml.size())) != 0)
    throw std::runtime_error("MuJoCo: cannot make the model's virtual file");
  std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), file)], xml.data(), xml.size());
  std::array<char, 1024> error{};
  mjModel* model = mj_loadXML(file, vfs.get(), error.data(), static_cast<int>(error.size()));
  mj_deleteVFS(vfs.get());
  if (model == nullptr)
    throw std::runtime_error(std::string("MuJoCo rejected the generated model: ") + error.data());
  return ModelPtr(model);
}

ModelPtr copyModel(const mjModel& model) {
  return ModelPtr(mj_copyModel(nullptr, &model));
}

DataPtr makeData(const mjModel& model) {
  return DataPtr(mj_makeData(&model));
}

WorldIndex indexWorld(const mjModel& model, const robot::RobotModel& robot) {
  WorldIndex index;
  index.object_body = findId(model, mjOBJ_BODY, kObjectBodyName);
  const int free = findId(model, mjOBJ_JOINT, kObjectBodyName);
  index.object_qpos = model.jnt_qposadr[free];
  index.object_dof = model.jnt_dofadr[free];
  const auto& links = robot.links();
  index.palm_body = findId(model, mjOBJ_BODY,
                           kRobotPrefix + links[static_cast<std::size_t>(robot.palmLink())].name);
  for (const std::string& name : robot.dofNames()) {
    const int joint = findId(model, mjOBJ_JOINT, kRobotPrefix + name);
    index.dof_qpos.push_back(model.jnt_qposadr[joint]);
    index.dof_velocity.push_back(model.jnt_dofadr[joint]);
    index.actuator.push_back(findId(model, mjOBJ_ACTUATOR, "servo/" + name));
  }
  for (const robot::Joint& joint : robot.joints()) {
    if (joint.dof < 0 || robot.dofNames()[static_cast<std::size_t>(joint.dof)] == joint.name)
      continue;
    const int id = findId(model, mjOBJ_JOINT, kRobotPrefix + joint.name);
    index.mimics.push_back({model.jnt_qposadr[id], joint.dof, joint.multiplier, joint.offset});
  }
  for (const robot::Fingertip& tip : robot.fingertips())
    index.fingertip_bodies.push_back(
        findId(model, mjOBJ_BODY, kRobotPrefix + links[static_cast<std::size_t>(tip.link)].name));
  return index;
}

void setRobotConfiguration(mjData& data, const WorldIndex& index, const Eigen::VectorXd& q) {
  for (std::size_t d = 0; d < index.dof_qpos.size(); ++d) {
    data.qpos[index.dof_qpos[d]] = q(static_cast<Eigen::Index>(d));
    data.qvel[index.dof_velocity[d]] = 0.0;
  }
  for (const WorldIndex::Mimic& mimic : index.mimics)
    data.qpos[mimic.qpos] = mimic.offset + mimic.multiplier * q(mimic.dof);
}

Eigen::VectorXd robotConfiguration(const mjData& data, const WorldIndex& index) {
  Eigen::VectorXd q(static_cast<Eigen::Index>(index.dof_qpos.size()));
  for (std::size_t d = 0; d < index.dof_qpos.size(); ++d)
    q(static_cast<Eigen::Index>(d)) = data.qpos[index.dof_qpos[d]];
  return q;
}

void setObjectPose(mjData& data, const WorldIndex& index, const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond q(pose.linear());
  mjtNum* qpos = data.qpos + index.object_qpos;
  const Eigen::Vector3d& p = pose.translation();
  const std::array<double, 7> values{p.x(), p.y(), p.z(), q.w(), q.x(), q.y(), q.z()};
  std::copy(values.begin(), values.end(), qpos);
  std::fill(data.qvel + index.object_dof, data.qvel + index.object_dof + 6, 0.0);
}

Eigen::Isometry3d bodyPose(const mjData& data, int body) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  const mjtNum* x = data.xpos + 3 * body;
  const mjtNum* m = data.xmat + 9 * body;
  pose.translation() << x[0], x[1], x[2];
  pose.linear() << m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8];
  return pose;
}

}  // namespace hfts::physics
