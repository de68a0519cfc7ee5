// Reading, writing and validating hand maps (schema: docs/database.md,
// "Hand reachability map").

#include <cmath>
#include <set>

#include "hdf5_file.h"
#include "hfts_db/hand_map.h"

namespace hfts::db {
namespace {

using h5::Handle;

[[noreturn]] void fail(const std::string& what, const std::string& problem) {
  throw DatabaseError(what + ": " + problem);
}

void checkNames(const std::vector<std::string>& names, const std::string& kind,
                const std::string& what) {
  if (names.empty()) fail(what, "no " + kind);
  if (std::set<std::string>(names.begin(), names.end()).size() != names.size())
    fail(what, kind + " are not unique");
  for (const std::string& name : names)
    if (name.empty() || name.find(',') != std::string::npos)
      fail(what, kind + " must be non-empty and free of commas: '" + name + "'");
}

void checkMatrix(const RowMatrixXd& m, Eigen::Index rows, Eigen::Index cols,
                 const std::string& name, const std::string& what) {
  if (m.rows() != rows || m.cols() != cols)
    fail(what, name + " has shape (" + std::to_string(m.rows()) + ", " + std::to_string(m.cols()) +
                   "), expected (" + std::to_string(rows) + ", " + std::to_string(cols) + ")");
  if (!m.allFinite()) fail(what, name + " holds a non-finite value");
}

void checkParameters(const HandMapParameters& p, const std::string& what) {
  if (p.num_samples == 0) fail(what, "num_samples must be positive");
  if (!(p.normal_weight > 0.0) || !std::isfinite(p.normal_weight))
    fail(what, "normal_weight must be positive");
  if (!(p.min_fingertip_distance >= 0.0) || !std::isfinite(p.min_fingertip_distance))
    fail(what, "min_fingertip_distance must be >= 0");
  if (!(p.friction >= 0.0) || !std::isfinite(p.friction)) fail(what, "friction must be >= 0");
}

void checkLimits(const HandMap& map, const std::string& what) {
  const auto d = static_cast<Eigen::Index>(map.dof_names.size());
  if (map.lower_limits.size() != d || map.upper_limits.size() != d)
    fail(what, "joint limits do not match the number of hand DoF");
  if (!map.lower_limits.allFinite() || !map.upper_limits.allFinite() ||
      (map.lower_limits.array() > map.upper_limits.array()).any())
    fail(what, "joint limits are not finite and ordered");
  for (Eigen::Index s = 0; s < map.configurations.rows(); ++s) {
    const auto q = map.configurations.row(s).transpose().array();
    if ((q < map.lower_limits.array() - 1e-9).any() || (q > map.upper_limits.array() + 1e-9).any())
      fail(what, "configuration " + std::to_string(s) + " is outside the joint limits");
  }
}

void checkUnitNormals(const RowMatrixXd& normals, const std::string& what) {
  for (Eigen::Index s = 0; s < normals.rows(); ++s)
    for (Eigen::Index c = 0; c + 2 < normals.cols(); c += 3)
      if (std::abs(normals.row(s).segment<3>(c).norm() - 1.0) > 1e-6)
        fail(what, "normal " + std::to_string(c / 3) + " of sample " + std::to_string(s) +
                       " is not a unit vector");
}

std::vector<hsize_t> shapeOf(const RowMatrixXd& m) {
  return {static_cast<hsize_t>(m.rows()), static_cast<hsize_t>(m.cols())};
}

RowMatrixXd readMatrix(hid_t group, const std::string& name) {
  const h5::Array<double> array = h5::readDoubles(group, name);
  if (array.shape.size() != 2) throw DatabaseError("dataset '" + name + "' must be 2-D");
  RowMatrixXd m(static_cast<Eigen::Index>(array.shape[0]),
                static_cast<Eigen::Index>(array.shape[1]));
  std::copy(array.data.begin(), array.data.end(), m.data());
  return m;
}

std::vector<double> asStd(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

Eigen::VectorXd asEigen(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

void writeParameters(hid_t file, const HandMapParameters& p) {
  Handle group = h5::createGroup(file, "parameters");
  h5::writeAttribute(group.id(), "num_samples", std::uint64_t{p.num_samples});
  h5::writeAttribute(group.id(), "max_draws", p.max_draws);
  h5::writeAttribute(group.id(), "seed", p.seed);
  h5::writeAttribute(group.id(), "normal_weight", p.normal_weight);
  h5::writeAttribute(group.id(), "min_fingertip_distance", p.min_fingertip_distance);
  h5::writeAttribute(group.id(), "friction", p.friction);
}

HandMapParameters readParameters(hid_t file) {
  Handle group = h5::openGroup(file, "parameters");
  HandMapParameters p;
  const std::uint64_t samples = h5::readUInt64(group.id(), "num_samples");
  if (samples > 0xffffffffULL) throw DatabaseError("attribute 'num_samples' is out of range");
  p.num_samples = static_cast<std::uint32_t>(samples);
  p.max_draws = h5::readUInt64(group.id(), "max_draws");
  p.seed = h5::readUInt64(group.id(), "seed");
  p.normal_weight = h5::readDouble(group.id(), "normal_weight");
  p.min_fingertip_distance = h5::readDouble(group.id(), "min_fingertip_distance");
  p.friction = h5::readDouble(group.id(), "friction");
  return p;
}

void writeAll(hid_t file, const HandMap& map) {
  h5::writeFormat(file, kHandMapFormatName, kHandMapFormatVersion);
  h5::writeAttribute(file, "producer", map.producer);
  h5::writeAttribute(file, "robot", map.robot_name);
  h5::writeAttribute(file, "units", std::string("m"));
  h5::writeAttribute(file, "frame", std::string("palm"));
  writeParameters(file, map.parameters);
  Handle hand = h5::createGroup(file, "hand");
  h5::writeAttribute(hand.id(), "dof_names", h5::joinNames(map.dof_names));
  h5::writeAttribute(hand.id(), "lower_limits", asStd(map.lower_limits));
  h5::writeAttribute(hand.id(), "upper_limits", asStd(map.upper_limits));
  h5::writeAttribute(hand.id(), "finger_names", h5::joinNames(map.finger_names));
  Handle samples = h5::createGroup(file, "samples");
  h5::writeAttribute(samples.id(), "num_draws", map.num_draws);
  h5::writeAttribute(samples.id(), "descriptor", map.descriptor);
  const auto write = [&samples](const char* name, const RowMatrixXd& m) {
    h5::writeDataset(samples.id(), name, m.data(), shapeOf(m));
  };
  write("configurations", map.configurations);
  write("positions", map.positions);
  write("normals", map.normals);
  write("descriptors", map.descriptors);
}

void readHeader(hid_t file, HandMap& map) {
  h5::checkFormat(file, kHandMapFormatName, kHandMapFormatVersion, "hand map",
                  "hfts-preprocess --hand ROBOT.json -o DIR");
  map.producer = h5::readStringAttribute(file, "producer");
  map.robot_name = h5::readStringAttribute(file, "robot");
}

HandMap readAll(hid_t file) {
  HandMap map;
  readHeader(file, map);
  map.parameters = readParameters(file);
  Handle hand = h5::openGroup(file, "hand");
  map.dof_names = h5::splitNames(h5::readStringAttribute(hand.id(), "dof_names"));
  map.lower_limits = asEigen(h5::readDoubleAttribute(hand.id(), "lower_limits"));
  map.upper_limits = asEigen(h5::readDoubleAttribute(hand.id(), "upper_limits"));
  map.finger_names = h5::splitNames(h5::readStringAttribute(hand.id(), "finger_names"));
  Handle samples = h5::openGroup(file, "samples");
  map.num_draws = h5::readUInt64(samples.id(), "num_draws");
  map.descriptor = h5::readStringAttribute(samples.id(), "descriptor");
  map.configurations = readMatrix(samples.id(), "configurations");
  map.positions = readMatrix(samples.id(), "positions");
  map.normals = readMatrix(samples.id(), "normals");
  map.descriptors = readMatrix(samples.id(), "descriptors");
  return map;
}

}  // namespace

void validateHandMap(const HandMap& map, const std::string& what) {
  if (map.robot_name.empty()) fail(what, "empty robot name");
  if (map.descriptor.empty()) fail(what, "empty descriptor name");
  checkNames(map.dof_names, "hand DoF names", what);
  checkNames(map.finger_names, "finger names", what);
  checkParameters(map.parameters, what);
  const Eigen::Index n = map.configurations.rows();
  const auto d = static_cast<Eigen::Index>(map.dof_names.size());
  const auto m3 = static_cast<Eigen::Index>(3 * map.finger_names.size());
  if (n == 0) fail(what, "no samples");
  if (map.num_draws < static_cast<std::uint64_t>(n)) fail(what, "num_draws < number of samples");
  checkMatrix(map.configurations, n, d, "configurations", what);
  checkMatrix(map.positions, n, m3, "positions", what);
  checkMatrix(map.normals, n, m3, "normals", what);
  if (map.descriptors.cols() == 0) fail(what, "descriptors have no columns");
  checkMatrix(map.descriptors, n, map.descriptors.cols(), "descriptors", what);
  checkLimits(map, what);
  checkUnitNormals(map.normals, what);
}

void saveHandMap(const HandMap& map, const std::filesystem::path& path) {
  const std::string what = "hand map '" + path.string() + "'";
  validateHandMap(map, what);
  h5::writeAtomically(path, what, [&map](hid_t file) { writeAll(file, map); });
}

HandMap loadHandMap(const std::filesystem::path& path) {
  const std::string what = "hand map '" + path.string() + "'";
  HandMap map;
  h5::readFile(path, what, [&map](hid_t file) { map = readAll(file); });
  validateHandMap(map, what);
  return map;
}

}  // namespace hfts::db
