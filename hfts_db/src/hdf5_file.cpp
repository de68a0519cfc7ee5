#include "hdf5_file.h"

#include <algorithm>
#include <sstream>
#include <utility>

#include "core/atomic_file.h"
#include "hfts_db/object_database.h"

namespace hfts::db::h5 {
namespace {

constexpr hsize_t kChunkRows = 4096;

[[noreturn]] void fail(const std::string& what) {
  throw DatabaseError(what);
}

void check(herr_t status, const std::string& what) {
  if (status < 0) fail(what);
}

/// HDF5 prints its error stack to stderr by default; our errors carry their
/// own message, so the stack is silenced once for the process.
void silenceErrorStack() {
  static std::once_flag once;
  std::call_once(once, [] { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); });
}

/// How a dataset is stored: chunked and checksummed, and for large
/// smooth data (distance grids) byte-shuffled and deflated first.
enum class Storage { kPlain, kCompressed };

Handle datasetCreationList(const std::vector<hsize_t>& shape, Storage storage) {
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "dataset property list");
  check(H5Pset_obj_track_times(dcpl.id(), false), "disabling timestamps");
  std::vector<hsize_t> chunk = shape;
  chunk[0] = std::clamp<hsize_t>(shape[0], 1, kChunkRows);
  for (std::size_t i = 1; i < chunk.size(); ++i) chunk[i] = std::max<hsize_t>(chunk[i], 1);
  check(H5Pset_chunk(dcpl.id(), static_cast<int>(chunk.size()), chunk.data()), "chunking");
  if (storage == Storage::kCompressed) {
    if (H5Zfilter_avail(H5Z_FILTER_DEFLATE) <= 0) fail("this HDF5 library has no deflate filter");
    check(H5Pset_shuffle(dcpl.id()), "byte shuffle");
    check(H5Pset_deflate(dcpl.id(), 6), "deflate");
  }
  // Last in the pipeline: the checksum covers the stored (compressed) bytes.
  check(H5Pset_fletcher32(dcpl.id()), "Fletcher32 checksum");
  return dcpl;
}

void writeRaw(hid_t parent, const std::string& name, hid_t type, const void* data,
              const std::vector<hsize_t>& shape, Storage storage = Storage::kPlain) {
  Handle space(H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr), H5Sclose,
               "dataspace of " + name);
  Handle dcpl = datasetCreationList(shape, storage);
  Handle set(
      H5Dcreate2(parent, name.c_str(), type, space.id(), H5P_DEFAULT, dcpl.id(), H5P_DEFAULT),
      H5Dclose, "creating dataset '" + name + "'");
  check(H5Dwrite(set.id(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
        "writing dataset '" + name + "'");
}

template <typename T>
Array<T> readRaw(hid_t parent, const std::string& name, hid_t memType, H5T_class_t expected,
                 std::size_t storedSize = 0) {
  if (!exists(parent, name)) fail("missing dataset '" + name + "'");
  Handle set(H5Dopen2(parent, name.c_str(), H5P_DEFAULT), H5Dclose,
             "opening dataset '" + name + "'");
  Handle type(H5Dget_type(set.id()), H5Tclose, "type of dataset '" + name + "'");
  if (H5Tget_class(type.id()) != expected)
    fail("dataset '" + name + "' has the wrong element type");
  if (storedSize != 0 && H5Tget_size(type.id()) != storedSize)
    fail("dataset '" + name + "' must hold " + std::to_string(8 * storedSize) + "-bit elements");
  Handle space(H5Dget_space(set.id()), H5Sclose, "dataspace of '" + name + "'");
  const int rank = H5Sget_simple_extent_ndims(space.id());
  if (rank < 1 || rank > 3) fail("dataset '" + name + "' has rank " + std::to_string(rank));
  Array<T> out;
  out.shape.resize(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.id(), out.shape.data(), nullptr);
  hsize_t count = 1;
  for (hsize_t d : out.shape) count *= d;
  constexpr hsize_t kMaxElements = hsize_t{1} << 31;
  if (count > kMaxElements) fail("dataset '" + name + "' is implausibly large");
  out.data.resize(static_cast<std::size_t>(count));
  if (count > 0 && H5Dread(set.id(), memType, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data.data()) < 0)
    fail("dataset '" + name + "' cannot be read (checksum mismatch or corrupt storage)");
  return out;
}

template <typename T>
void writeAttributeRaw(hid_t object, const std::string& name, hid_t type,
                       const std::vector<T>& values, bool scalar) {
  const hsize_t n = values.size();
  // An empty array needs HDF5's null dataspace: a simple one cannot be empty.
  const hid_t spaceId = scalar   ? H5Screate(H5S_SCALAR)
                        : n == 0 ? H5Screate(H5S_NULL)
                                 : H5Screate_simple(1, &n, nullptr);
  Handle space(spaceId, H5Sclose, "attribute space");
  Handle attr(H5Acreate2(object, name.c_str(), type, space.id(), H5P_DEFAULT, H5P_DEFAULT),
              H5Aclose, "creating attribute '" + name + "'");
  if (n > 0 || scalar)
    check(H5Awrite(attr.id(), type, values.data()), "writing attribute '" + name + "'");
}

template <typename T>
std::vector<T> readAttributeRaw(hid_t object, const std::string& name, hid_t memType,
                                H5T_class_t expected) {
  if (H5Aexists(object, name.c_str()) <= 0) fail("missing attribute '" + name + "'");
  Handle attr(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose,
              "opening attribute '" + name + "'");
  Handle type(H5Aget_type(attr.id()), H5Tclose, "attribute type");
  if (H5Tget_class(type.id()) != expected) fail("attribute '" + name + "' has the wrong type");
  Handle space(H5Aget_space(attr.id()), H5Sclose, "attribute space");
  const hssize_t n = H5Sget_simple_extent_npoints(space.id());
  if (n < 0 || n > 1024) fail("attribute '" + name + "' has an implausible size");
  std::vector<T> values(static_cast<std::size_t>(n));
  if (n > 0) check(H5Aread(attr.id(), memType, values.data()), "reading attribute '" + name + "'");
  return values;
}

}  // namespace

std::mutex& libraryMutex() {
  static std::mutex mutex;
  return mutex;
}

Handle::Handle(hid_t id, herr_t (*close)(hid_t), const std::string& what) : id_(id), close_(close) {
  if (id_ < 0) fail(what + " failed");
}

Handle::Handle(Handle&& other) noexcept
    : id_(std::exchange(other.id_, H5I_INVALID_HID)), close_(other.close_) {}

Handle& Handle::operator=(Handle&& other) noexcept {
  std::swap(id_, other.id_);
  std::swap(close_, other.close_);
  return *this;
}

Handle::~Handle() {
  if (id_ >= 0 && close_ != nullptr) close_(id_);
}

void writeAtomically(const std::filesystem::path& path, const std::string& what,
                     const std::function<void(hid_t file)>& fill) {
  const std::filesystem::path tmp = core::temporarySibling(path);
  try {
    {
      std::lock_guard<std::mutex> lock(libraryMutex());
      Handle file = createFile(tmp);
      fill(file.id());
      if (H5Fflush(file.id(), H5F_SCOPE_GLOBAL) < 0) fail("flushing failed");
    }
    std::filesystem::rename(tmp, path);
  } catch (const std::exception& e) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw DatabaseError(what + ": " + e.what());
  }
}

void readFile(const std::filesystem::path& path, const std::string& what,
              const std::function<void(hid_t file)>& read) {
  try {
    std::lock_guard<std::mutex> lock(libraryMutex());
    Handle file = openFile(path);
    read(file.id());
  } catch (const std::exception& e) {
    throw DatabaseError(what + ": " + e.what());
  }
}

std::string joinNames(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& name : names) out += (out.empty() ? "" : ",") + name;
  return out;
}

std::vector<std::string> splitNames(const std::string& text) {
  std::vector<std::string> names;
  std::stringstream stream(text);
  for (std::string name; std::getline(stream, name, ',');) names.push_back(name);
  return names;
}

void writeFormat(hid_t file, const std::string& name, std::uint64_t version) {
  writeAttribute(file, "format", name);
  writeAttribute(file, "format_version", version);
}

void checkFormat(hid_t file, const std::string& name, std::uint64_t version,
                 const std::string& kind, const std::string& rebuild) {
  if (H5Aexists(file, "format") <= 0 || H5Aexists(file, "format_version") <= 0)
    fail("not an HFTS " + kind);
  // The version first: strings of other versions may be stored differently
  // (version 1 kept them in HDF5's global heap) and are not read.
  const std::uint64_t found = readUInt64(file, "format_version");
  if (found != version)
    fail("format version " + std::to_string(found) +
         " is not supported (this program reads version " + std::to_string(version) +
         "); rebuild it with " + rebuild);
  const std::string format = readStringAttribute(file, "format");
  if (format != name) fail("not an HFTS " + kind + " (format '" + format + "')");
}

Handle createFile(const std::filesystem::path& path) {
  silenceErrorStack();
  Handle fcpl(H5Pcreate(H5P_FILE_CREATE), H5Pclose, "file creation list");
  check(H5Pset_obj_track_times(fcpl.id(), false), "disabling timestamps");
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "file access list");
  // The 1.10 format checksums all metadata, so corruption is detected
  // instead of being parsed.
  check(H5Pset_libver_bounds(fapl.id(), H5F_LIBVER_V110, H5F_LIBVER_V110), "format bounds");
  return Handle(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl.id(), fapl.id()), H5Fclose,
                "creating HDF5 file");
}

Handle openFile(const std::filesystem::path& path) {
  silenceErrorStack();
  if (!std::filesystem::is_regular_file(path)) fail("no such file");
  if (H5Fis_hdf5(path.c_str()) <= 0) fail("not an HDF5 file");
  return Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose,
                "opening the HDF5 file (truncated or corrupt)");
}

Handle createGroup(hid_t parent, const std::string& name) {
  Handle gcpl(H5Pcreate(H5P_GROUP_CREATE), H5Pclose, "group creation list");
  check(H5Pset_obj_track_times(gcpl.id(), false), "disabling timestamps");
  return Handle(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, gcpl.id(), H5P_DEFAULT), H5Gclose,
                "creating group '" + name + "'");
}

Handle openGroup(hid_t parent, const std::string& name) {
  if (!exists(parent, name)) fail("missing group '" + name + "'");
  return Handle(H5Gopen2(parent, name.c_str(), H5P_DEFAULT), H5Gclose,
                "opening group '" + name + "'");
}

bool exists(hid_t parent, const std::string& name) {
  return H5Lexists(parent, name.c_str(), H5P_DEFAULT) > 0;
}

void writeDataset(hid_t parent, const std::string& name, const double* data,
                  const std::vector<hsize_t>& shape) {
  writeRaw(parent, name, H5T_IEEE_F64LE, data, shape);
}

void writeDataset(hid_t parent, const std::string& name, const float* data,
                  const std::vector<hsize_t>& shape) {
  writeRaw(parent, name, H5T_IEEE_F32LE, data, shape, Storage::kCompressed);
}

void writeDataset(hid_t parent, const std::string& name, const std::uint32_t* data,
                  const std::vector<hsize_t>& shape) {
  writeRaw(parent, name, H5T_STD_U32LE, data, shape);
}

Array<double> readDoubles(hid_t parent, const std::string& name) {
  return readRaw<double>(parent, name, H5T_NATIVE_DOUBLE, H5T_FLOAT);
}

Array<float> readFloats(hid_t parent, const std::string& name) {
  // Exactly f32: converting f64 would round to nearest, and a distance
  // grid's values must stay rounded down.
  return readRaw<float>(parent, name, H5T_NATIVE_FLOAT, H5T_FLOAT, sizeof(float));
}

Array<std::uint32_t> readUInt32s(hid_t parent, const std::string& name) {
  return readRaw<std::uint32_t>(parent, name, H5T_NATIVE_UINT32, H5T_INTEGER);
}

void writeAttribute(hid_t object, const std::string& name, const std::string& value) {
  if (value.size() >= kMaxStringAttribute)
    fail("attribute '" + name + "' is longer than " + std::to_string(kMaxStringAttribute) +
         " bytes");
  if (value.find('\0') != std::string::npos) fail("attribute '" + name + "' holds a NUL byte");
  // Fixed length, stored in the (checksummed) attribute message itself:
  // variable-length strings live in HDF5's global heap, which is not
  // checksummed and which libhdf5 1.10 reads unsafely from corrupted files.
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "string type");
  check(H5Tset_size(type.id(), value.size() + 1), "string size");
  check(H5Tset_strpad(type.id(), H5T_STR_NULLTERM), "string padding");
  check(H5Tset_cset(type.id(), H5T_CSET_UTF8), "string charset");
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, "attribute space");
  Handle attr(H5Acreate2(object, name.c_str(), type.id(), space.id(), H5P_DEFAULT, H5P_DEFAULT),
              H5Aclose, "creating attribute '" + name + "'");
  check(H5Awrite(attr.id(), type.id(), value.c_str()), "writing attribute '" + name + "'");
}

void writeAttribute(hid_t object, const std::string& name, double value) {
  writeAttributeRaw(object, name, H5T_IEEE_F64LE, std::vector<double>{value}, true);
}

void writeAttribute(hid_t object, const std::string& name, std::uint64_t value) {
  writeAttributeRaw(object, name, H5T_STD_U64LE, std::vector<std::uint64_t>{value}, true);
}

void writeAttribute(hid_t object, const std::string& name, const std::vector<double>& values) {
  writeAttributeRaw(object, name, H5T_IEEE_F64LE, values, false);
}

void writeAttribute(hid_t object, const std::string& name,
                    const std::vector<std::uint64_t>& values) {
  writeAttributeRaw(object, name, H5T_STD_U64LE, values, false);
}

std::string readStringAttribute(hid_t object, const std::string& name) {
  if (H5Aexists(object, name.c_str()) <= 0) fail("missing attribute '" + name + "'");
  Handle attr(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose,
              "opening attribute '" + name + "'");
  Handle fileType(H5Aget_type(attr.id()), H5Tclose, "attribute type");
  if (H5Tget_class(fileType.id()) != H5T_STRING || H5Tis_variable_str(fileType.id()) != 0)
    fail("attribute '" + name + "' is not a fixed-length string");
  const std::size_t size = H5Tget_size(fileType.id());
  if (size == 0 || size > kMaxStringAttribute)
    fail("attribute '" + name + "' has an invalid string length " + std::to_string(size));
  Handle space(H5Aget_space(attr.id()), H5Sclose, "attribute space");
  if (H5Sget_simple_extent_type(space.id()) != H5S_SCALAR)
    fail("attribute '" + name + "' is not a single string");
  Handle memType(H5Tcopy(H5T_C_S1), H5Tclose, "string type");
  check(H5Tset_size(memType.id(), size), "string size");
  check(H5Tset_strpad(memType.id(), H5T_STR_NULLPAD), "string padding");
  check(H5Tset_cset(memType.id(), H5Tget_cset(fileType.id())), "string charset");
  std::string text(size, '\0');
  check(H5Aread(attr.id(), memType.id(), text.data()), "reading attribute '" + name + "'");
  text.resize(std::min(text.find('\0'), text.size()));
  return text;
}

std::vector<double> readDoubleAttribute(hid_t object, const std::string& name) {
  return readAttributeRaw<double>(object, name, H5T_NATIVE_DOUBLE, H5T_FLOAT);
}

std::vector<std::uint64_t> readUInt64Attribute(hid_t object, const std::string& name) {
  return readAttributeRaw<std::uint64_t>(object, name, H5T_NATIVE_UINT64, H5T_INTEGER);
}

double readDouble(hid_t object, const std::string& name) {
  const std::vector<double> values = readDoubleAttribute(object, name);
  if (values.size() != 1) fail("attribute '" + name + "' must hold one value");
  return values[0];
}

std::uint64_t readUInt64(hid_t object, const std::string& name) {
  const std::vector<std::uint64_t> values = readUInt64Attribute(object, name);
  if (values.size() != 1) fail("attribute '" + name + "' must hold one value");
  return values[0];
}

}  // namespace hfts::db::h5
