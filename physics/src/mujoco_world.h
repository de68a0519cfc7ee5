#pragma once
// Private to physics/src: MuJoCo models and data as owned objects, and
// where the robot's DoF, its fingertips and the object live in a compiled
// model of mjcfScene().

#include <mujoco/mujoco.h>

#include <Eigen/Geometry>

#include <memory>
#include <string>
#include <vector>

#include "robot/robot_model.h"

namespace hfts::physics {

struct ModelDeleter {
  void operator()(mjModel* model) const { mj_deleteModel(model); }
};
struct DataDeleter {
  void operator()(mjData* data) const { mj_deleteData(data); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

/// Compiles MJCF text, handed to MuJoCo through its virtual file system (no
/// file is written). MuJoCo's XML compiler keeps global state, so calls
/// are serialised. Throws std::runtime_error with MuJoCo's message.
ModelPtr compileMjcf(const std::string& xml);

/// A copy of `model` (to perturb it without touching the original).
ModelPtr copyModel(const mjModel& model);
DataPtr makeData(const mjModel& model);

/// An error inside MuJoCo while simulating (its mju_error, e.g. its stack
/// exhausted), turned into an exception instead of exiting the process.
class SimulationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Installs the process-wide MuJoCo handlers once: errors throw
/// SimulationError, warnings are left to mjData::warning (read by the
/// trials) instead of being printed and logged to MUJOCO_LOG.TXT, and the
/// contact filter of contact_filter.h (the same contacts, found sooner).
void installMujocoHandlers();

/// Where the parts of mjcfScene()'s model are.
struct WorldIndex {
  int object_body = -1;
  int object_qpos = -1;  ///< the free joint's 7 qpos (position, quaternion w x y z)
  int object_dof = -1;   ///< its 6 dof
  int palm_body = -1;
  /// Per robot DoF: qpos and dof address of its joint, and its servo.
  std::vector<int> dof_qpos, dof_velocity, actuator;
  struct Mimic {
    int qpos = -1;
    int dof = -1;  ///< the robot DoF it follows
    double multiplier = 1.0, offset = 0.0;
  };
  std::vector<Mimic> mimics;
  std::vector<int> fingertip_bodies;  ///< per fingertip of the robot
};

/// Finds everything by the names mjcfScene() gives. Throws
/// std::logic_error when the model is not one of its (a programming error).
WorldIndex indexWorld(const mjModel& model, const robot::RobotModel& robot);

/// Puts the robot at configuration q (numDofs values; mimic joints follow),
/// at rest.
void setRobotConfiguration(mjData& data, const WorldIndex& index, const Eigen::VectorXd& q);

/// The robot's DoF values now.
Eigen::VectorXd robotConfiguration(const mjData& data, const WorldIndex& index);

/// Places the object's free body at `pose`, at rest.
void setObjectPose(mjData& data, const WorldIndex& index, const Eigen::Isometry3d& pose);

/// A body's frame in the world (after mj_forward or a step).
Eigen::Isometry3d bodyPose(const mjData& data, int body);

}  // namespace hfts::physics
