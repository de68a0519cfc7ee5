#pragma once
// The bundled hand's reachability, for grasp tests that need no planner.

#include "grasp/hand_map_builder.h"
#include "grasp/hand_reachability.h"
#include "robot_fixture.h"

namespace hfts::test {

/// R(h) of the KR5 + SDH from a freshly built hand map (default query
/// options), built once per test program.
inline const grasp::HandReachability& kr5SdhReachability() {
  static const grasp::HandReachability r(kr5Sdh(), grasp::buildHandMap(kr5Sdh()));
  return r;
}

}  // namespace hfts::test
