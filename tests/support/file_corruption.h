#pragma once
// Damaging database files on purpose: truncation and bit flips.

#include <gtest/gtest.h>
#include <hdf5.h>

#include <filesystem>
#include <functional>
#include <string>

#include "test_meshes.h"

namespace hfts::test {

/// Writes `bytes` cut to several lengths into `scratch` and expects `load`
/// to throw `Error` for each.
template <typename Error>
void expectTruncationIsRejected(const std::string& bytes, const std::filesystem::path& scratch,
                                const std::function<void(const std::filesystem::path&)>& load) {
  for (const double fraction : {0.0001, 0.01, 0.3, 0.7, 0.99}) {
    const auto length = static_cast<std::size_t>(fraction * static_cast<double>(bytes.size()));
    writeText(scratch, bytes.substr(0, length));
    SCOPED_TRACE(length);
    EXPECT_THROW(load(scratch), Error);
  }
}

/// Flips one bit at `flips` places spread over `bytes`: wherever it lands,
/// `loadAndCompare` must either throw `Error` (detected) or load content
/// equal to the original (the flip hit unused bytes; the callback checks
/// that). Returns how many flips were detected.
template <typename Error>
int countDetectedBitFlips(const std::string& bytes, const std::filesystem::path& scratch,
                          std::size_t flips,
                          const std::function<void(const std::filesystem::path&)>& loadAndCompare) {
  int detected = 0;
  const std::size_t step = std::max<std::size_t>(1, bytes.size() / flips);
  for (std::size_t offset = 0; offset < bytes.size(); offset += step) {
    std::string flipped = bytes;
    flipped[offset] = static_cast<char>(flipped[offset] ^ (1 << (offset % 8)));
    writeText(scratch, flipped);
    SCOPED_TRACE(offset);
    try {
      loadAndCompare(scratch);
    } catch (const Error&) {
      ++detected;
    }
  }
  return detected;
}

/// Writes a valid HDF5 file that is not one of ours (one group, no format).
inline void writeForeignHdf5(const std::filesystem::path& path) {
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  H5Gclose(H5Gcreate2(file, "data", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  H5Fclose(file);
}

/// Overwrites the root `format_version` attribute of one of our files.
inline void setFormatVersion(const std::filesystem::path& path, std::uint64_t version) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hid_t attr = H5Aopen(file, "format_version", H5P_DEFAULT);
  H5Awrite(attr, H5T_NATIVE_UINT64, &version);
  H5Aclose(attr);
  H5Fclose(file);
}

/// Replaces the attribute `name` of the object at `object` ("/" for the
/// root) with a variable-length string, as format version 1 stored strings.
inline void setVariableLengthString(const std::filesystem::path& path, const std::string& object,
                                    const std::string& name, const std::string& value) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hid_t target = H5Oopen(file, object.c_str(), H5P_DEFAULT);
  H5Adelete(target, name.c_str());
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, H5T_VARIABLE);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr = H5Acreate2(target, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
  const char* text = value.c_str();
  H5Awrite(attr, type, &text);
  H5Aclose(attr);
  H5Sclose(space);
  H5Tclose(type);
  H5Oclose(target);
  H5Fclose(file);
}

}  // namespace hfts::test
