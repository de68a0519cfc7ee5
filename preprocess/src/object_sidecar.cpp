#include "preprocess/object_sidecar.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/invalid_argument.h"
#include "hfts_db/object_database.h"

namespace hfts::preprocess {
namespace {

std::string number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

}  // namespace

void checkDensity(double density, const std::string& field) {
  if (!std::isfinite(density) || density < db::kMinDensity || density > db::kMaxDensity)
    throw InvalidArgument(field, "must be in [" + number(db::kMinDensity) + ", " +
                                     number(db::kMaxDensity) + "] kg/m^3, got " + number(density));
}

std::filesystem::path sidecarPath(const std::filesystem::path& meshPath) {
  return meshPath.parent_path() / (meshPath.stem().string() + ".json");
}

ObjectSidecar readSidecar(const std::filesystem::path& meshPath) {
  const std::filesystem::path path = sidecarPath(meshPath);
  ObjectSidecar out;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return out;
  const std::string file = "sidecar '" + path.string() + "'";
  std::ifstream in(path);
  if (!in) throw InvalidArgument(file, "cannot be read");
  const nlohmann::json json = nlohmann::json::parse(in, nullptr, false);
  if (json.is_discarded()) throw InvalidArgument(file, "is not valid JSON");
  if (!json.is_object())
    throw InvalidArgument(file, "must be a JSON object such as {\"density\": 2300}");
  for (const auto& [key, value] : json.items()) {
    if (key != "density")
      throw InvalidArgument(file + ": " + key, "unknown key (a sidecar may hold: density)");
    if (!value.is_number())
      throw InvalidArgument(file + ": density", "must be a number (kg/m^3), got " + value.dump());
    out.density = value.get<double>();
    checkDensity(*out.density, file + ": density");
  }
  return out;
}

}  // namespace hfts::preprocess
