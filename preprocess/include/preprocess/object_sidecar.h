#pragma once
// What a mesh file cannot say about its object, in a JSON file beside it:
// `<mesh stem>.json`, e.g. objects/meshes/mug.json next to mug.ply.

#include <filesystem>
#include <optional>
#include <string>

namespace hfts::preprocess {

/// The keys a sidecar may hold; every key is optional.
struct ObjectSidecar {
  /// Density of the object's material (kg/m^3), db::kMinDensity..kMaxDensity.
  std::optional<double> density;
};

/// Throws hfts::InvalidArgument naming `field` unless the density is finite
/// and within db::kMinDensity..kMaxDensity (kg/m^3).
void checkDensity(double density, const std::string& field);

/// Where the sidecar of a mesh is: `<mesh stem>.json` in its directory.
std::filesystem::path sidecarPath(const std::filesystem::path& meshPath);

/// The sidecar of `meshPath`, or no keys if there is none. Throws
/// hfts::InvalidArgument whose field names the file and the key ("sidecar
/// 'mug.json': density"): for a file that is not a JSON object, an unknown
/// key, or a density that is not a number within db::kMinDensity..kMaxDensity.
ObjectSidecar readSidecar(const std::filesystem::path& meshPath);

}  // namespace hfts::preprocess
