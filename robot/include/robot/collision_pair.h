#pragma once
// What a collision query names when it finds a contact.

#include <string>

namespace hfts::robot {

/// The first colliding pair found, for diagnostics.
struct CollisionPair {
  std::string first;
  std::string second;
};

}  // namespace hfts::robot
