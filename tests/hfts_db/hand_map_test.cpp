#include "hfts_db/hand_map.h"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <functional>

#include "file_corruption.h"
#include "grasp/hand_reachability.h"
#include "test_meshes.h"

namespace hfts::db {
namespace {

using test::TempDir;

/// A real (small) map of the KR5's SDH, built once for the suite.
const HandMap& sample() {
  static const HandMap map = [] {
    const auto model = robot::RobotModel::load(std::filesystem::path(HFTS_SOURCE_DIR) /
                                               "robots/kr5_sdh/kr5_sdh.json");
    grasp::HandMapOptions options;
    options.num_samples = 2000;
    return grasp::buildHandMap(model, options);
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
  test::writeForeignHdf5(dir / "foreign.h5");
  expectLoadError(dir / "foreign.h5", "not an HFTS hand map");
}

TEST(HandMap, OtherFormatVersionsAreRejected) {
  TempDir dir;
  saveHandMap(sample(), dir / "v.h5");
  test::setFormatVersion(dir / "v.h5", 3);
  expectLoadError(dir / "v.h5", "format version 3 is not supported");
  test::setFormatVersion(dir / "v.h5", 1);
  test::setVariableLengthString(dir / "v.h5", "/", "format", "hfts-hand-map");
  test::expectErrorMentioning<DatabaseError>(
      [&] { loadHandMap(dir / "v.h5"); },
      {"format version 1 is not supported", "hfts-preprocess --hand ROBOT.json -o DIR"});
}

TEST(HandMap, TruncatedFilesAreRejected) {
  TempDir dir;
  saveHandMap(sample(), dir / "full.h5");
  test::expectTruncationIsRejected<DatabaseError>(
      test::readBytes(dir / "full.h5"), dir / "cut.h5",
      [](const std::filesystem::path& p) { loadHandMap(p); });
}

TEST(HandMap, BitFlipsAreDetectedOrHarmless) {
  TempDir dir;
  saveHandMap(sample(), dir / "full.h5");
  const int detected = test::countDetectedBitFlips<DatabaseError>(
      test::readBytes(dir / "full.h5"), dir / "flip.h5", 200,
      [](const std::filesystem::path& p) { expectSame(loadHandMap(p), sample()); });
  EXPECT_GT(detected, 150);  // nearly all of the file is checksummed data
}

}  // namespace
}  // namespace hfts::db
