#pragma once
// The JSON form of grasp quality requests and results, shared by
// hfts-quality and the service's grasp.quality method.

#include <string>

#include "grasp/grasp_quality.h"

namespace hfts::grasp {

/// Parses {"contacts": [{"position": [x,y,z], "normal": [x,y,z]}, ...],
/// "normals": "inward" | "outward" (default inward), "center": [x,y,z]
/// (default origin), "torque_scale": rho (default 1), "friction": mu
/// (default 0.5), "cone_edges": K (default 8), "torsional_friction": gamma
/// (m, default 0: hard fingers)}. Throws std::invalid_argument
/// naming the field for malformed JSON, unknown keys, wrong types or
/// lengths, non-finite numbers and values out of range.
GraspQualityRequest graspQualityRequestFromJson(const std::string& text);

/// {"epsilon": value}
std::string graspQualityResultToJson(const GraspQualityResult& result);

}  // namespace hfts::grasp
