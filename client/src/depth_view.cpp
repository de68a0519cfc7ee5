#include "depth_view.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "core/base64.h"

namespace hfts::client {
namespace {

using nlohmann::json;

constexpr std::string_view kPngMagic("\x89PNG\r\n\x1a\n", 8);
constexpr std::string_view kNpyMagic("\x93NUMPY", 6);

/// `option` 'path': problem.
[[noreturn]] void refuse(const char* option, const std::string& path, const std::string& problem) {
  throw std::runtime_error(std::string(option) + " '" + path + "': " + problem);
}

std::string fileBytes(const char* option, const std::string& path) {
  // A regular file only: opening a FIFO would wait for a writer.
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) refuse(option, path, "cannot read the file");
  std::ifstream in(path, std::ios::binary);
  if (!in) refuse(option, path, "cannot read the file");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

bool startsWith(const std::string& bytes, std::string_view magic) {
  return std::string_view(bytes).substr(0, magic.size()) == magic;
}

/// The camera file's object, checked.
json cameraOf(const std::string& path) {
  json camera;
  try {
    camera = json::parse(fileBytes("--camera", path));
  } catch (const json::parse_error& e) {
    // Not e.what(): it quotes what it read, which may be binary.
    refuse("--camera", path, "not valid JSON (at byte " + std::to_string(e.byte) + ")");
  }
  if (!camera.is_object())
    refuse("--camera", path, "must be a JSON object with the camera's intrinsics and pose");
  for (const char* key : {"type", "file", "png_base64", "npy_base64", "mask", "mask_base64"})
    if (camera.contains(key))
      refuse("--camera", path,
             std::string("'") + key + "' is the image's: --depth and --mask give the image");
  for (const char* key : {"intrinsics", "pose"})
    if (!camera.contains(key)) refuse("--camera", path, std::string("has no '") + key + "'");
  return camera;
}

}  // namespace

json depthView(const std::string& depth, const std::string& camera, const std::string& mask) {
  const std::string image = fileBytes("--depth", depth);
  const bool png = startsWith(image, kPngMagic);
  if (!png && !startsWith(image, kNpyMagic))
    refuse("--depth", depth, "neither a PNG nor a NumPy .npy file");
  json view = {{"type", "depth_image"}, {"name", "camera"}, {"units", png ? "mm" : "m"}};
  view.update(cameraOf(camera));  // the camera's name and units win
  view[png ? "png_base64" : "npy_base64"] = core::base64Encode(image);
  if (!mask.empty()) {
    const std::string bytes = fileBytes("--mask", mask);
    if (!startsWith(bytes, kPngMagic)) refuse("--mask", mask, "not a PNG file");
    view["mask_base64"] = core::base64Encode(bytes);
  }
  return view;
}

}  // namespace hfts::client
