#pragma once
// Thin RAII layer over the HDF5 C API, private to hfts_db. Every dataset is
// chunked and Fletcher32-checksummed (f32 ones also compressed), no object
// carries a timestamp (so the same content gives the same bytes), and every
// failure becomes a DatabaseError naming the object that failed.

#include <hdf5.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

namespace hfts::db::h5 {

/// The HDF5 library shipped by Debian is not built thread-safe: every use
/// of it goes through this lock.
std::mutex& libraryMutex();

/// Owns one HDF5 identifier and closes it with the matching H5?close.
class Handle {
 public:
  Handle() = default;
  Handle(hid_t id, herr_t (*close)(hid_t), const std::string& what);
  Handle(Handle&& other) noexcept;
  Handle& operator=(Handle&& other) noexcept;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle();
  hid_t id() const { return id_; }

 private:
  hid_t id_ = H5I_INVALID_HID;
  herr_t (*close_)(hid_t) = nullptr;
};

/// Writes a new HDF5 file at `path` atomically: `fill` writes its content
/// into a temporary sibling (holding libraryMutex()), which is flushed,
/// closed and renamed over `path`. On any failure the temporary file is
/// removed, an existing file is left untouched and a DatabaseError
/// "<what>: <problem>" is thrown.
void writeAtomically(const std::filesystem::path& path, const std::string& what,
                     const std::function<void(hid_t file)>& fill);

/// Opens `path` read-only and calls `read` on it, holding libraryMutex().
/// Every failure becomes a DatabaseError "<what>: <problem>".
void readFile(const std::filesystem::path& path, const std::string& what,
              const std::function<void(hid_t file)>& read);

/// Lists of names are stored as one comma-separated string attribute.
std::string joinNames(const std::vector<std::string>& names);
/// The inverse; keeps empty items, so a reader can reject them.
std::vector<std::string> splitNames(const std::string& text);

/// Root attributes `format` (string) and `format_version` (u64) naming a
/// file's schema.
void writeFormat(hid_t file, const std::string& name, std::uint64_t version);
/// Throws "not an HFTS <kind>" unless the root `format` is `name`; unless
/// `format_version` is `version`, names both versions and the command that
/// rebuilds the file (`rebuild`, e.g. "hfts-preprocess MESH -o DIR").
void checkFormat(hid_t file, const std::string& name, std::uint64_t version,
                 const std::string& kind, const std::string& rebuild);

/// Creates a new file (truncating) with deterministic layout settings.
Handle createFile(const std::filesystem::path& path);
/// Opens an existing file read-only; throws if it is not an HDF5 file.
Handle openFile(const std::filesystem::path& path);

Handle createGroup(hid_t parent, const std::string& name);
Handle openGroup(hid_t parent, const std::string& name);
bool exists(hid_t parent, const std::string& name);

/// A dataset's content with its shape; rank 1 to 3.
template <typename T>
struct Array {
  std::vector<T> data;
  std::vector<hsize_t> shape;
};

void writeDataset(hid_t parent, const std::string& name, const double* data,
                  const std::vector<hsize_t>& shape);
void writeDataset(hid_t parent, const std::string& name, const std::uint32_t* data,
                  const std::vector<hsize_t>& shape);
/// Single-precision reals (distance grids), stored as IEEE f32, byte-shuffled
/// and deflated (level 6) before the checksum.
void writeDataset(hid_t parent, const std::string& name, const float* data,
                  const std::vector<hsize_t>& shape);
Array<double> readDoubles(hid_t parent, const std::string& name);
Array<float> readFloats(hid_t parent, const std::string& name);
Array<std::uint32_t> readUInt32s(hid_t parent, const std::string& name);

/// Strings are scalar fixed-length attributes (NUL-terminated, UTF-8) of at
/// most kMaxStringAttribute bytes.
inline constexpr std::size_t kMaxStringAttribute = std::size_t{1} << 16;
void writeAttribute(hid_t object, const std::string& name, const std::string& value);
/// Scalars are written as HDF5 scalars, vectors always as 1-D arrays.
void writeAttribute(hid_t object, const std::string& name, double value);
void writeAttribute(hid_t object, const std::string& name, std::uint64_t value);
void writeAttribute(hid_t object, const std::string& name, const std::vector<double>& values);
void writeAttribute(hid_t object, const std::string& name,
                    const std::vector<std::uint64_t>& values);
/// Whether `object` carries the attribute (for attributes added to a schema
/// version after files of it were written).
bool hasAttribute(hid_t object, const std::string& name);
std::string readStringAttribute(hid_t object, const std::string& name);
std::vector<double> readDoubleAttribute(hid_t object, const std::string& name);
std::vector<std::uint64_t> readUInt64Attribute(hid_t object, const std::string& name);
/// Reads an attribute that must hold exactly one value.
double readDouble(hid_t object, const std::string& name);
std::uint64_t readUInt64(hid_t object, const std::string& name);

}  // namespace hfts::db::h5
