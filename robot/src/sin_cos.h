#pragma once
// Sines and cosines of a few angles at once in SIMD (Highway; chosen at
// run time), for forward kinematics. Internal to the robot library.

#include <cstddef>

namespace hfts::robot {

/// sines[i] = sin(angles[i]), cosines[i] = cos(angles[i]) for i < count;
/// within a few units in the last place of std::sin and std::cos.
void sinCos(const double* angles, std::size_t count, double* sines, double* cosines);

}  // namespace hfts::robot
