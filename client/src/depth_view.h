#pragma once
// What a depth camera sees, for a plan request (hfts-client plan --depth
// FILE --camera JSON [--mask FILE]): a depth_image obstacle with its image
// inline in base64 (docs/point_clouds.md#in-a-plan-request). The client
// decodes no image: the server does.

#include <nlohmann/json.hpp>

#include <string>

namespace hfts::client {

/// A depth_image obstacle for the request's `obstacles`: the image of
/// `depth` (a 16-bit PNG or a float32 .npy, told by their magic bytes) as
/// `png_base64` or `npy_base64`, the mask PNG `mask` (empty: none) as
/// `mask_base64`, and the keys of the JSON object in `camera`: `intrinsics`
/// and `pose` (required), `name` (default "camera"), `units` (default mm
/// for a PNG, m for a .npy), `min_depth`, `max_depth`, `voxel`, `radius`,
/// `shadow`, `outliers`. Throws std::runtime_error naming the option, the
/// file and the problem: a file that cannot be read or is of the wrong
/// kind, a camera that is not a JSON object, lacks a required key or has
/// one of the image's (`type`, `file`, `png_base64`, `npy_base64`,
/// `mask`, `mask_base64`).
nlohmann::json depthView(const std::string& depth, const std::string& camera,
                         const std::string& mask);

}  // namespace hfts::client
