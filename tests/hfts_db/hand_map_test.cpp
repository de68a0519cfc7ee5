#include "hfts_db/hand_map.h"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <functional>

#include "planner/hand_reachability.h"
#include "test_meshes.h"

namespace hfts::db {
namespace {

using test::TempDir;

/// A real (small) map of the KR5's SDH, built once for the suite.
const HandMap& sample() {
  static const HandMap map = [] {
    const auto model = planner::RobotModel::load(std::filesystem::path(HFTS_SOURCE_DIR) /
                                                 "robots/kr5_sdh/kr5_sdh.json");
    planner::HandMapOptions options;
    options.num_samples = 2000;
    return planner::buildHandMap(model, options);
  }();
  return map;
}

void expectSame(const HandMap& a, const HandMap& b) {
  EXPECT_EQ(a.robot_name, b.robot_name);
  EXPECT_EQ(a.producer, b.producer);
  EXPECT_EQ(a.dof_names, b.dof_names);
  EXPECT_EQ(a.lower_limits, b.lower_limits);
  EXPECT_EQ(a.upper_limits, b.upper_limits);
  EXPECT_EQ(a.finger_names, b.finger_names);
  EXPECT_EQ(a.descriptor, b.descriptor);
  EXPECT_EQ(a.parameters.num_samples, b.parameters.num_samples);
  EXPECT_EQ(a.parameters.max_draws, b.parameters.max_draws);
  EXPECT_EQ(a.parameters.seed, b.parameters.seed);
  EXPECT_EQ(a.parameters.normal_weight, b.parameters.normal_weight);
  EXPECT_EQ(a.parameters.min_fingertip_distance, b.parameters.min_fingertip_distance);
  EXPECT_EQ(a.parameters.friction, b.parameters.friction);
  EXPECT_EQ(a.num_draws, b.num_draws);
  EXPECT_EQ(a.configurations, b.configurations);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.descriptors, b.descriptors);
}

void expectLoadError(const std::filesystem::path& path, const std::string& problem) {
  test::expectErrorMentioning<DatabaseError>([&] { loadHandMap(path); }, {path.string(), problem});
}

TEST(HandMap, RoundTripKeepsEveryFieldExactly) {
  TempDir dir;
  saveHandMap(sample(), dir / "sdh.h5");
  expectSame(sample(), loadHandMap(dir / "sdh.h5"));
}

TEST(HandMap, SameMapGivesSameBytesAndNoTemporaryFiles) {
  TempDir dir;
  saveHandMap(sample(), dir / "a.h5");
  saveHandMap(sample(), dir / "b.h5");
  saveHandMap(sample(), dir / "b.h5");
  EXPECT_EQ(test::readBytes(dir / "a.h5"), test::readBytes(dir / "b.h5"));
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir.path()))
    ++files;
  EXPECT_EQ(files, 2u);
}

TEST(HandMap, InvalidContentIsNotWrittenAndTheOldFileSurvives) {
  TempDir dir;
  saveHandMap(sample(), dir / "sdh.h5");
  const std::string before = test::readBytes(dir / "sdh.h5");
  HandMap broken = sample();
  broken.normals(7, 4) += 0.1;
  test::expectErrorMentioning<DatabaseError>([&] { saveHandMap(broken, dir / "sdh.h5"); },
                                             {"sdh.h5", "normal 1 of sample 7"});
  EXPECT_EQ(test::readBytes(dir / "sdh.h5"), before);
  EXPECT_THROW(saveHandMap(sample(), dir / "no" / "such" / "dir.h5"), DatabaseError);
}

TEST(HandMap, ValidationNamesTheViolation) {
  const std::vector<std::pair<std::function<void(HandMap&)>, std::string>> cases = {
      {[](HandMap& m) { m.robot_name.clear(); }, "empty robot name"},
      {[](HandMap& m) { m.dof_names[1] = m.dof_names[0]; }, "not unique"},
      {[](HandMap& m) { m.finger_names[0] = "a,b"; }, "commas"},
      {[](HandMap& m) { m.positions(3, 3) = NAN; }, "positions holds a non-finite value"},
      {[](HandMap& m) { m.normals.conservativeResize(m.normals.rows() - 1, 9); },
       "normals has shape"},
      {[](HandMap& m) { m.configurations(5, 1) = 4.0; }, "configuration 5 is outside"},
      {[](HandMap& m) { m.lower_limits.resize(2); }, "joint limits"},
      {[](HandMap& m) { m.parameters.normal_weight = 0; }, "normal_weight"},
      {[](HandMap& m) { m.num_draws = 1; }, "num_draws"},
      {[](HandMap& m) { m.descriptors.resize(m.descriptors.rows(), 0); }, "descriptors"}};
  for (const auto& [edit, problem] : cases) {
    HandMap map = sample();
    edit(map);
    SCOPED_TRACE(problem);
    test::expectErrorMentioning<DatabaseError>([&] { validateHandMap(map, "the map"); },
                                               {"the map", problem});
  }
}

TEST(HandMap, MissingEmptyAndForeignFilesAreRejected) {
  TempDir dir;
  expectLoadError(dir / "missing.h5", "no such file");
  test::writeText(dir / "text.h5", "this is not a hand map\n");
  expectLoadError(dir / "text.h5", "not an HDF5 file");
  const hid_t file =
      H5Fcreate((dir / "foreign.h5").c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  H5Gclose(H5Gcreate2(file, "data", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  H5Fclose(file);
  expectLoadError(dir / "foreign.h5", "not an HFTS hand map");
}

TEST(HandMap, OtherFormatVersionsAreRejected) {
  TempDir dir;
  saveHandMap(sample(), dir / "v.h5");
  const hid_t file = H5Fopen((dir / "v.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hid_t attr = H5Aopen(file, "format_version", H5P_DEFAULT);
  const std::uint64_t version = 2;
  H5Awrite(attr, H5T_NATIVE_UINT64, &version);
  H5Aclose(attr);
  H5Fclose(file);
  expectLoadError(dir / "v.h5", "format version 2 is not supported");
}

TEST(HandMap, TruncatedFilesAreRejected) {
  TempDir dir;
  saveHandMap(sample(), dir / "full.h5");
  const std::string bytes = test::readBytes(dir / "full.h5");
  for (const double fraction : {0.0001, 0.01, 0.3, 0.7, 0.99}) {
    const auto length = static_cast<std::size_t>(fraction * static_cast<double>(bytes.size()));
    test::writeText(dir / "cut.h5", bytes.substr(0, length));
    SCOPED_TRACE(length);
    EXPECT_THROW(loadHandMap(dir / "cut.h5"), DatabaseError);
  }
}

TEST(HandMap, BitFlipsAreDetectedOrHarmless) {
  // Wherever a bit flips, loading either fails with a DatabaseError or
  // yields exactly the original content (the flip hit unused bytes).
  TempDir dir;
  saveHandMap(sample(), dir / "full.h5");
  const std::string bytes = test::readBytes(dir / "full.h5");
  int detected = 0;
  const std::size_t step = std::max<std::size_t>(1, bytes.size() / 200);
  for (std::size_t offset = 0; offset < bytes.size(); offset += step) {
    std::string flipped = bytes;
    flipped[offset] = static_cast<char>(flipped[offset] ^ (1 << (offset % 8)));
    test::writeText(dir / "flip.h5", flipped);
    SCOPED_TRACE(offset);
    try {
      expectSame(loadHandMap(dir / "flip.h5"), sample());
    } catch (const DatabaseError&) {
      ++detected;
    }
  }
  EXPECT_GT(detected, 150);  // nearly all of the file is checksummed data
}

}  // namespace
}  // namespace hfts::db
