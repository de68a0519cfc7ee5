// Scene JSON text through parseScene (as loadScene and inline scenes use
// it), then the target's pose. Mesh obstacles may name the small meshes
// copied into a scratch folder; inputs naming other paths are skipped (a
// scene file may name any mesh of the machine, which is the operator's
// choice, not an input to fuzz). A bad scene must throw SceneError.

#include <unistd.h>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "robot/scene.h"

namespace {

namespace fs = std::filesystem;

const fs::path& meshDir() {
  static const fs::path dir = [] {
    const fs::path d =
        fs::temp_directory_path() / ("hfts_fuzz_meshes_" + std::to_string(::getpid()));
    fs::create_directories(d);
    for (const char* mesh : {"small_cube.stl", "tile.obj", "l_bracket.ply"})
      fs::copy_file(fs::path(HFTS_SOURCE_DIR) / "objects/meshes" / mesh, d / mesh,
                    fs::copy_options::overwrite_existing);
    return d;
  }();
  return dir;
}

/// Whether every mesh the scene names is a plain file name.
bool onlyLocalMeshes(const nlohmann::json& scene) {
  if (!scene.is_object() || !scene.contains("obstacles") || !scene["obstacles"].is_array())
    return true;
  for (const nlohmann::json& o : scene["obstacles"])
    if (o.is_object() && o.contains("mesh") && o["mesh"].is_string() &&
        !hfts::robot::isSafeName(o["mesh"].get<std::string>()))
      return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hfts;
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (!onlyLocalMeshes(nlohmann::json::parse(text, nullptr, false))) return -1;
  try {
    const robot::Scene scene = robot::parseScene(text, meshDir(), "fuzz scene");
    for (const robot::Placement& p : scene.placements)
      robot::targetPose(scene.withPlacement(p.name), Vertices::Identity(3, 3));
    robot::targetPose(scene, Vertices::Identity(3, 3));
  } catch (const robot::SceneError&) {
  }
  return 0;
}
