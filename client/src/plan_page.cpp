#include "client/plan_page.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/base64.h"

namespace hfts::client {
namespace {

std::string readFile(const std::filesystem::path& path, const std::string& hint) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read '" + path.string() + "'" + hint);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Text that ends no <script> element early: "</" becomes "<\/" (the same
/// string in JavaScript and in JSON).
std::string scriptSafe(std::string text) {
  for (std::size_t at = text.find("</"); at != std::string::npos; at = text.find("</", at + 3))
    text.replace(at, 2, "<\\/");
  return text;
}

void replaceOnce(std::string& page, const std::string& marker, const std::string& with) {
  const std::size_t at = page.find(marker);
  if (at == std::string::npos) throw std::runtime_error("the viewer's page.html has no " + marker);
  page.replace(at, marker.size(), with);
}

}  // namespace

std::string planPage(const nlohmann::json& plan, const std::string& glbBytes,
                     const std::filesystem::path& viewerDir) {
  const auto success = plan.is_object() ? plan.find("success") : plan.end();
  if (success == plan.end() || *success != true)
    throw std::runtime_error("not a successful plan result (hfts-client --out PLAN.json plan ...)");
  if (!plan.contains("trajectory") || !plan.at("trajectory").is_object())
    throw std::runtime_error("the plan has no trajectory (its trajectory_rate was 0)");
  std::string glb = glbBytes;
  if (glb.empty()) {
    if (!plan.contains("gltf") || !plan.at("gltf").is_string())
      throw std::runtime_error(
          "the plan has no glTF: plan with --gltf PLAN.glb, or give the .glb with --glb");
    glb = core::base64Decode(plan.at("gltf").get<std::string>(), "gltf");
  }
  if (glb.size() < 12 || glb.compare(0, 4, "glTF") != 0)
    throw std::runtime_error("the glTF is not a binary glTF (.glb)");
  nlohmann::json shown = plan;
  shown.erase("gltf");
  const std::string hint = " (build the viewer: scripts/setup.sh)";
  std::string page = readFile(viewerDir / "src" / "page.html", hint);
  const std::string viewer = readFile(viewerDir / "dist" / "viewer.js", hint);
  replaceOnce(page, "/*HFTS_TITLE*/",
              shown.value("scene", std::string()) + ", " + shown.value("object", std::string()));
  replaceOnce(page, "/*HFTS_DATA*/",
              "window.HFTS_PLAN = " + scriptSafe(shown.dump()) + ";\nwindow.HFTS_GLB_BASE64 = \"" +
                  core::base64Encode(glb) + "\";");
  replaceOnce(page, "/*HFTS_VIEWER*/", scriptSafe(viewer));
  return page;
}

}  // namespace hfts::client
