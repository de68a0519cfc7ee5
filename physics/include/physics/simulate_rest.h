#pragma once
// Does an object stay where it is put? Released at rest on its support, in
// MuJoCo, with the scene's obstacles and no robot: the physics check of a
// placement (docs/placement.md).

#include <Eigen/Geometry>

#include <optional>
#include <string>

#include "hfts_db/object_database.h"
#include "robot/scene.h"

namespace hfts::physics {

/// The protocol; the defaults are issue 48's "stays within 1 cm and 5
/// degrees for 2 s". Checked by simulateRest (InvalidArgument naming
/// "options.<field>").
struct RestOptions {
  /// kg/m^3 (> 0); unset: the object's own (objectDensity()).
  std::optional<double> density;
  double friction = 0.5;            ///< of every contact (>= 0), as the grasp check's
  double duration = 2.0;            ///< s simulated after the release (> 0)
  double max_displacement = 0.01;   ///< m (> 0) the centre of mass may move
  double max_rotation = 0.0872665;  ///< rad (> 0, 5 degrees) the object may turn
  double timestep = 0.002;          ///< MuJoCo's time step (s, in (0, 0.005])
};

struct RestVerdict {
  /// Both within their limits for the whole duration.
  bool stable = false;
  double displacement = 0.0;  ///< largest distance of the centre of mass from where released (m)
  double rotation = 0.0;      ///< largest turn from the orientation released in (rad)
  /// Empty when stable; else what went beyond its limit first and when
  /// ("moved 12.0 mm by 0.84 s", "turned 9.2 degrees by 0.31 s").
  std::string failure;
};

/// Checks rest options (InvalidArgument "options.<field>").
void validateRestOptions(const RestOptions& options);

/// Releases `object` (a free body of its density, colliding as
/// collisionPieces()) at rest at `pose` among `scene`'s obstacles (its
/// robot and target are not simulated) and simulates `options.duration`
/// seconds under gravity. Deterministic. Throws InvalidArgument
/// ("options.<field>", "pose") for bad options or a non-finite pose.
RestVerdict simulateRest(const robot::Scene& scene, const db::ObjectDatabase& object,
                         const Eigen::Isometry3d& pose, const RestOptions& options = {});

}  // namespace hfts::physics
