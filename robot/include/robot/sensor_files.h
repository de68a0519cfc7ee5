#pragma once
// Sensor files: point clouds (PCD, PLY: PCL's readers behind a check of
// the header), depth images (16-bit PNG, float32 .npy: libpng and a small
// reader) and segmentation masks (8-bit PNG), read and written
// (docs/point_clouds.md).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hfts_db/triangle_mesh.h"
#include "robot/point_cloud.h"

namespace hfts::robot {

/// Reads the points of a PCD (ASCII or binary) or PLY file (PCL's readers;
/// the format by the extension). Throws hfts::InvalidArgument ("file")
/// for a file that cannot be read, holds no points or has non-finite ones
/// only (non-finite points are dropped).
Vertices readPointCloud(const std::filesystem::path& path);

/// A cloud's points and, when the file has them (PCD normal_x, normal_y,
/// normal_z; PLY nx, ny, nz), its normals, one per point (zero where a
/// point's normal is not finite).
struct SensedPoints {
  Vertices points;
  std::optional<Vertices> normals;
};

/// readPointCloud with the file's normals; the same errors.
SensedPoints readPointCloudWithNormals(const std::filesystem::path& path);

/// Reads a depth image: a 16-bit single-channel PNG (values times
/// `scale` give metres: 0.001 for millimetres) or a NumPy .npy file of
/// float32 (little-endian, two dimensions, C order; times `scale`).
/// Throws hfts::InvalidArgument ("file", "scale").
DepthImage readDepthImage(const std::filesystem::path& path, double scale);

/// Reads a segmentation mask: an 8-bit grey PNG, 1 where not 0 (the
/// pixels of the object to pick, left out of the obstacle). Throws
/// hfts::InvalidArgument ("mask").
std::vector<std::uint8_t> readMask(const std::filesystem::path& path);

/// The same from a file's bytes (a request's inline image): a 16-bit PNG,
/// a float32 .npy or an 8-bit mask PNG. Throws hfts::InvalidArgument
/// (`field`, or "scale") naming the problem.
DepthImage decodeDepthPng(std::string_view bytes, double scale, const std::string& field);
DepthImage decodeDepthNpy(std::string_view bytes, double scale, const std::string& field);
std::vector<std::uint8_t> decodeMaskPng(std::string_view bytes, const std::string& field);

/// A depth image as a 16-bit PNG in millimetres (what readDepthImage reads
/// with scale 0.001; depths beyond 65.535 m or unseen are 0), and a mask as
/// an 8-bit PNG (255 where set).
std::string encodeDepthPng(const DepthImage& image);
std::string encodeMaskPng(const std::vector<std::uint8_t>& mask, int width, int height);

}  // namespace hfts::robot
