#pragma once
// The fixed set of model perturbations a grasp must hold under: what we do
// not know well (friction, the object's mass, the servo gains), each
// changed alone to both sides (docs/physics.md#perturbations).

#include <string>
#include <vector>

namespace hfts::physics {

/// Factors applied to the nominal model for one trial.
struct Perturbation {
  std::string name;
  double friction_scale = 1.0;  ///< sliding and torsional friction of every geom
  double mass_scale = 1.0;      ///< the object's mass and inertia (its density)
  double gain_scale = 1.0;      ///< the hand servos' kp and kv
};

/// The nominal model first, then (when `perturb`) friction x0.75 and
/// x1.25, mass x0.75 and x1.25, hand servo gains x0.5 and x2: seven trials.
std::vector<Perturbation> perturbations(bool perturb);

}  // namespace hfts::physics
