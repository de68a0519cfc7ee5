#include "robot/sensor_files.h"

#include <pcl/console/print.h>
#include <pcl/conversions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "core/invalid_argument.h"

namespace hfts::robot {
namespace {

[[noreturn]] void refuse(const std::string& field, const std::string& problem) {
  throw InvalidArgument(field, problem);
}

/// The words of a header line.
std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

/// What PCL's readers assume of a header and do not check (a PCD without
/// FIELDS crashes PCDReader::read): the header of a PCD or PLY file with
/// x, y and z and at least one point, or the problem.
std::string headerProblem(const std::filesystem::path& path, bool pcd) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  bool x = false, y = false, z = false, data = false;
  long long points = -1;
  if (!pcd && (!std::getline(in, line) || line.rfind("ply", 0) != 0)) return "not a PLY file";
  bool inVertex = false;
  auto mark = [&](const std::string& field) {
    x = x || field == "x";
    y = y || field == "y";
    z = z || field == "z";
  };
  for (int n = 0; n < 1000 && std::getline(in, line); ++n) {
    const std::vector<std::string> w = words(line);
    if (w.empty() || w[0][0] == '#' || w[0] == "comment") continue;
    if (pcd && w[0] == "FIELDS") {
      for (const std::string& f : w) mark(f);
    } else if (pcd && w[0] == "POINTS" && w.size() == 2) {
      points = std::atoll(w[1].c_str());
    } else if (pcd && w[0] == "DATA") {
      data = w.size() == 2 && (w[1] == "ascii" || w[1] == "binary" || w[1] == "binary_compressed");
      break;
    } else if (!pcd && w[0] == "element") {
      inVertex = w.size() == 3 && w[1] == "vertex";
      if (inVertex) points = std::atoll(w[2].c_str());
    } else if (!pcd && w[0] == "property" && inVertex && w.size() >= 3) {
      mark(w.back());
    } else if (!pcd && w[0] == "end_header") {
      data = true;
      break;
    }
  }
  if (!(x && y && z)) return pcd ? "has no FIELDS x y z" : "has no vertex properties x y z";
  if (points <= 0) return "holds no point";
  if (!data)
    return pcd ? "has no DATA ascii, binary or binary_compressed line" : "has no end_header";
  return {};
}

/// A single-channel PNG's values, row-major.
struct GreyImage {
  int width = 0, height = 0;
  std::vector<std::uint16_t> values;
};

void pngError(png_structp png, png_const_charp message) {
  *static_cast<std::string*>(png_get_error_ptr(png)) = message;
  png_longjmp(png, 1);
}

void pngWarning(png_structp, png_const_charp) {}

/// libpng's reader over bytes in memory.
struct ByteSource {
  std::string_view bytes;
  std::size_t offset = 0;
};

void readBytes(png_structp png, png_bytep data, png_size_t length) {
  auto* source = static_cast<ByteSource*>(png_get_io_ptr(png));
  if (length > source->bytes.size() - source->offset) png_error(png, "truncated");
  std::memcpy(data, source->bytes.data() + source->offset, length);
  source->offset += length;
}

/// Decodes a grey PNG of `bits` (8 or 16) bits per pixel from `bytes`;
/// throws InvalidArgument(field) naming `what` and the problem.
GreyImage decodeGreyPng(std::string_view bytes, int bits, const std::string& field,
                        const std::string& what) {
  ByteSource source{bytes};
  std::string problem;  // libpng's errors come back here (pngError), not printed
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &problem, &pngError, &pngWarning);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  if (info == nullptr) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    refuse(field, "cannot start reading " + what);
  }
  GreyImage image;
  std::vector<png_byte> row;
  // libpng reports errors by longjmp: nothing with a destructor may be
  // made between here and the end of the reading below.
  if (setjmp(png_jmpbuf(png))) {
    problem = "not a readable PNG (" + problem + ")";
  } else {
    png_set_read_fn(png, &source, &readBytes);
    png_read_info(png, info);
    const png_uint_32 width = png_get_image_width(png, info),
                      height = png_get_image_height(png, info);
    if (png_get_bit_depth(png, info) != bits ||
        png_get_color_type(png, info) != PNG_COLOR_TYPE_GRAY) {
      problem = "must be a " + std::to_string(bits) + "-bit single-channel (grey) PNG";
    } else if (width == 0 || height == 0 || width > 16384 || height > 16384) {
      problem = "must be 1 to 16384 pixels wide and high";
    } else {
      image.width = static_cast<int>(width);
      image.height = static_cast<int>(height);
      image.values.resize(std::size_t{width} * height);
      row.resize(png_get_rowbytes(png, info));
      for (png_uint_32 y = 0; y < height; ++y) {
        png_read_row(png, row.data(), nullptr);
        for (png_uint_32 x = 0; x < width; ++x)
          image.values[std::size_t{y} * width + x] = static_cast<std::uint16_t>(
              bits == 8 ? row[x] : (unsigned{row[2 * x]} << 8) | row[2 * x + 1]);  // big-endian
      }
    }
  }
  png_destroy_read_struct(&png, &info, nullptr);
  if (!problem.empty()) refuse(field, what + ": " + problem);
  return image;
}

void appendBytes(png_structp png, png_bytep data, png_size_t length) {
  static_cast<std::string*>(png_get_io_ptr(png))
      ->append(reinterpret_cast<const char*>(data), length);
}

/// A grey PNG of `bits` (8 or 16) bits per pixel, as bytes.
std::string encodeGreyPng(const GreyImage& image, int bits) {
  std::string bytes, problem;
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, &problem, &pngError, &pngWarning);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  std::vector<png_byte> row(std::size_t(image.width) * (bits / 8));
  if (info == nullptr || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("PNG encoding failed: " + problem);
  }
  png_set_write_fn(png, &bytes, &appendBytes, nullptr);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.width),
               static_cast<png_uint_32>(image.height), bits, PNG_COLOR_TYPE_GRAY,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const std::uint16_t v =
          image.values[std::size_t(y) * std::size_t(image.width) + std::size_t(x)];
      if (bits == 8) {
        row[std::size_t(x)] = static_cast<png_byte>(v);
      } else {
        row[std::size_t(2 * x)] = static_cast<png_byte>(v >> 8);
        row[std::size_t(2 * x + 1)] = static_cast<png_byte>(v & 0xff);
      }
    }
    png_write_row(png, row.data());
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return bytes;
}

/// The whole file, or InvalidArgument(field).
std::string fileBytes(const std::filesystem::path& path, const std::string& field) {
  // A regular file only: opening a FIFO would wait for a writer.
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error))
    refuse(field, "cannot read '" + path.string() + "'");
  std::ifstream in(path, std::ios::binary);
  if (!in) refuse(field, "cannot read '" + path.string() + "'");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

GreyImage readGreyPng(const std::filesystem::path& path, int bits, const std::string& field) {
  return decodeGreyPng(fileBytes(path, field), bits, field, "'" + path.string() + "'");
}

DepthImage depthOf(const GreyImage& grey, double scale) {
  DepthImage image{grey.width, grey.height, std::vector<float>(grey.values.size())};
  for (std::size_t i = 0; i < grey.values.size(); ++i)
    image.depths[i] = static_cast<float>(grey.values[i] * scale);
  return image;
}

std::vector<std::uint8_t> maskOf(const GreyImage& grey) {
  std::vector<std::uint8_t> mask(grey.values.size());
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = grey.values[i] != 0 ? 1 : 0;
  return mask;
}

DepthImage readPng(const std::filesystem::path& path, double scale) {
  return depthOf(readGreyPng(path, 16, "file"), scale);
}

/// The value of `key` in a .npy header's dictionary text, up to the next
/// ',' at depth 0 or the closing '}'.
std::string npyField(const std::string& header, const std::string& key) {
  const std::size_t at = header.find("'" + key + "'");
  if (at == std::string::npos) return {};
  std::size_t start = header.find(':', at);
  if (start == std::string::npos) return {};
  int depth = 0;
  std::size_t end = ++start;
  for (; end < header.size(); ++end) {
    const char c = header[end];
    if (c == '(') ++depth;
    if (c == ')') --depth;
    if (depth == 0 && (c == ',' || c == '}')) break;
  }
  std::string value = header.substr(start, end - start);
  value.erase(std::remove(value.begin(), value.end(), ' '), value.end());
  return value;
}

/// Decodes a NumPy .npy array of float32 (little-endian, two dimensions, C
/// order) from `bytes`, times `scale`; throws InvalidArgument(field) naming
/// `what` and the problem.
DepthImage decodeNpy(std::string_view bytes, double scale, const std::string& field,
                     const std::string& what) {
  const auto fail = [&](const std::string& problem) { refuse(field, what + ": " + problem); };
  // Magic, major and minor version, then the header's length: 2 bytes in
  // version 1, 4 in versions 2 and 3 (little-endian).
  if (bytes.size() < 8 || bytes.substr(0, 6) != std::string_view("\x93NUMPY", 6))
    fail("not a NumPy .npy file");
  const std::size_t lengthBytes = bytes[6] == 1 ? 2 : 4;
  if (bytes.size() < 8 + lengthBytes) fail("truncated header");
  std::size_t length = 0;
  for (std::size_t i = lengthBytes; i-- > 0;)
    length = (length << 8) | static_cast<unsigned char>(bytes[8 + i]);
  if (length > 65536) fail("header too long");
  const std::size_t start = 8 + lengthBytes;
  if (bytes.size() - start < length) fail("truncated header");
  const std::string header(bytes.substr(start, length));
  if (npyField(header, "descr") != "'<f4'")
    fail("must hold float32 ('<f4'), not " + npyField(header, "descr"));
  if (npyField(header, "fortran_order") != "False") fail("must be in C order");
  const std::string shape = npyField(header, "shape");
  int height = 0, width = 0;
  if (std::sscanf(shape.c_str(), "(%d,%d)", &height, &width) != 2 || height <= 0 || width <= 0 ||
      height > 16384 || width > 16384)
    fail("must be a 2-D array of 1 to 16384 rows and columns, shape " + shape);
  const std::size_t values = std::size_t(width) * std::size_t(height);
  const std::string_view data = bytes.substr(start + length);
  if (data.size() < values * sizeof(float)) fail("holds fewer values than its shape " + shape);
  DepthImage image{width, height, std::vector<float>(values)};
  std::memcpy(image.depths.data(), data.data(), values * sizeof(float));
  for (float& d : image.depths) d = static_cast<float>(static_cast<double>(d) * scale);
  return image;
}

void checkScale(double scale) {
  if (!std::isfinite(scale) || scale <= 0.0)
    refuse("scale", "must be a positive factor to metres, not " + std::to_string(scale));
}

}  // namespace

SensedPoints readPointCloudWithNormals(const std::filesystem::path& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error))
    refuse("file", "cannot read '" + path.string() + "'");
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension != ".pcd" && extension != ".ply")
    refuse("file", "'" + path.string() + "': must be a .pcd or .ply point cloud");
  const std::string problem = headerProblem(path, extension == ".pcd");
  if (!problem.empty()) refuse("file", "'" + path.string() + "': " + problem);
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);  // errors come back as ours
  pcl::PCLPointCloud2 blob;
  int status = -1;
  if (extension == ".pcd") {
    pcl::PCDReader reader;
    status = reader.read(path.string(), blob);
  } else {
    pcl::PLYReader reader;
    status = reader.read(path.string(), blob);
  }
  if (status < 0) refuse("file", "'" + path.string() + "': not a readable point cloud");
  // PCL names a PLY's nx, ny, nz normal_x, normal_y, normal_z too.
  const auto has = [&](const char* name) {
    return std::any_of(blob.fields.begin(), blob.fields.end(),
                       [&](const pcl::PCLPointField& f) { return f.name == name; });
  };
  const bool withNormals = has("normal_x") && has("normal_y") && has("normal_z");
  pcl::PointCloud<pcl::PointNormal> cloud;
  pcl::fromPCLPointCloud2(blob, cloud);
  SensedPoints out;
  out.points.resize(static_cast<Eigen::Index>(cloud.size()), 3);
  Vertices normals(static_cast<Eigen::Index>(cloud.size()), 3);
  Eigen::Index n = 0;
  for (const pcl::PointNormal& p : cloud) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    out.points.row(n) << static_cast<double>(p.x), static_cast<double>(p.y),
        static_cast<double>(p.z);
    const Eigen::Vector3d normal(static_cast<double>(p.normal_x), static_cast<double>(p.normal_y),
                                 static_cast<double>(p.normal_z));
    normals.row(n) = (normal.allFinite() ? normal : Eigen::Vector3d::Zero()).transpose();
    ++n;
  }
  out.points.conservativeResize(n, 3);
  if (out.points.rows() == 0) refuse("file", "'" + path.string() + "': holds no finite point");
  if (withNormals) {
    normals.conservativeResize(n, 3);
    out.normals = std::move(normals);
  }
  return out;
}

Vertices readPointCloud(const std::filesystem::path& path) {
  return readPointCloudWithNormals(path).points;
}

DepthImage readDepthImage(const std::filesystem::path& path, double scale) {
  checkScale(scale);
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".png") return readPng(path, scale);
  if (extension == ".npy")
    return decodeNpy(fileBytes(path, "file"), scale, "file", "'" + path.string() + "'");
  refuse("file", "'" + path.string() + "': must be a 16-bit .png or a float32 .npy depth image");
}

std::vector<std::uint8_t> readMask(const std::filesystem::path& path) {
  return maskOf(readGreyPng(path, 8, "mask"));
}

DepthImage decodeDepthPng(std::string_view bytes, double scale, const std::string& field) {
  checkScale(scale);
  return depthOf(decodeGreyPng(bytes, 16, field, "the image"), scale);
}

DepthImage decodeDepthNpy(std::string_view bytes, double scale, const std::string& field) {
  checkScale(scale);
  return decodeNpy(bytes, scale, field, "the image");
}

std::vector<std::uint8_t> decodeMaskPng(std::string_view bytes, const std::string& field) {
  return maskOf(decodeGreyPng(bytes, 8, field, "the mask"));
}

std::string encodeDepthPng(const DepthImage& image) {
  GreyImage grey{image.width, image.height, std::vector<std::uint16_t>(image.depths.size())};
  for (std::size_t i = 0; i < grey.values.size(); ++i) {
    const double mm = std::round(static_cast<double>(image.depths[i]) * 1000.0);
    grey.values[i] =
        std::isfinite(mm) && mm > 0 && mm <= 65535 ? static_cast<std::uint16_t>(mm) : 0;
  }
  return encodeGreyPng(grey, 16);
}

std::string encodeMaskPng(const std::vector<std::uint8_t>& mask, int width, int height) {
  GreyImage grey{width, height, std::vector<std::uint16_t>(mask.size())};
  for (std::size_t i = 0; i < mask.size(); ++i) grey.values[i] = mask[i] != 0 ? 255 : 0;
  return encodeGreyPng(grey, 8);
}

}  // namespace hfts::robot
