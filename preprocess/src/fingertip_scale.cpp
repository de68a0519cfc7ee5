#include "preprocess/fingertip_scale.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/invalid_argument.h"

namespace hfts::preprocess {

db::BuildParameters resolveFilterScales(db::BuildParameters p, double samplesPerSquareMetre) {
  if (!(p.pad_radius > 0.0) || !std::isfinite(p.pad_radius))
    throw InvalidArgument(
        "pad_radius", "must be a positive number of metres, got " + std::to_string(p.pad_radius));
  if (!(samplesPerSquareMetre > 0.0) || !std::isfinite(samplesPerSquareMetre))
    throw InvalidArgument("samplesPerSquareMetre", "must be positive and finite, got " +
                                                       std::to_string(samplesPerSquareMetre));
  if (p.patch_radius == 0.0) p.patch_radius = kPatchPerPad * p.pad_radius;
  if (p.min_neighbours == 0) {
    const double perPatch = samplesPerSquareMetre * M_PI * p.patch_radius * p.patch_radius;
    p.min_neighbours =
        static_cast<std::uint32_t>(std::clamp(std::round(kNeighbourShare * perPatch), 1.0, 1e6));
  }
  return p;
}

}  // namespace hfts::preprocess
