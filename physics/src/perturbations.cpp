// The trials' perturbations (perturbations.h).
#include "physics/perturbations.h"

namespace hfts::physics {

std::vector<Perturbation> perturbations(bool perturb) {
  std::vector<Perturbation> out{{"nominal", 1.0, 1.0, 1.0}};
  if (!perturb) return out;
  // Friction of everyday contact pairs is rarely known better than +-25 %,
  // nor is a default density; servo gains are our guesses (a factor 2).
  out.push_back({"friction_low", 0.75, 1.0, 1.0});
  out.push_back({"friction_high", 1.25, 1.0, 1.0});
  out.push_back({"mass_low", 1.0, 0.75, 1.0});
  out.push_back({"mass_high", 1.0, 1.25, 1.0});
  out.push_back({"gain_low", 1.0, 1.0, 0.5});
  out.push_back({"gain_high", 1.0, 1.0, 2.0});
  return out;
}

}  // namespace hfts::physics
