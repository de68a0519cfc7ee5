#pragma once
// hfts-client view: a plan (its JSON result and animated glTF) as one
// self-contained HTML page with the viewer (viewer/, docs/viewer.md).

#include <nlohmann/json_fwd.hpp>

#include <filesystem>
#include <string>

namespace hfts::client {

/// The page: viewer/src/page.html with the plan JSON (without its `gltf`),
/// the .glb (base64) and the bundled viewer (viewer/dist/viewer.js, made by
/// scripts/setup.sh) inlined, so it opens from disk without a server.
/// `glbBytes` empty: the plan's own `gltf` field. Throws
/// std::runtime_error naming what is missing: a failed plan, a plan
/// without trajectory or glTF, a viewer that is not built.
std::string planPage(const nlohmann::json& plan, const std::string& glbBytes,
                     const std::filesystem::path& viewerDir);

}  // namespace hfts::client
