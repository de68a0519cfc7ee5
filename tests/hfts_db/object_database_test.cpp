#include <gtest/gtest.h>
#include <hdf5.h>

#include <fstream>

#include "file_corruption.h"
#include "hfts_db/atomic_file.h"
#include "hfts_db/object_database.h"
#include "preprocess/database_builder.h"
#include "test_meshes.h"

namespace hfts::db {
namespace {

using test::TempDir;

/// A real database, built once for the whole suite.
const ObjectDatabase& sample() {
  static const ObjectDatabase db = [] {
    BuildParameters params;
    params.sample_density = 60000;
    return preprocess::buildObjectDatabaseFromFile(test::bundledMeshDir() / "torus.stl", params)
        .database;
  }();
  return db;
}

void expectSame(const ObjectDatabase& a, const ObjectDatabase& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.source_mesh, b.source_mesh);
  EXPECT_EQ(a.source_sha256, b.source_sha256);
  EXPECT_EQ(a.producer, b.producer);
  EXPECT_EQ(a.parameters.branching, b.parameters.branching);
  EXPECT_EQ(a.parameters.filters, b.parameters.filters);
  EXPECT_EQ(a.parameters.seed, b.parameters.seed);
  EXPECT_EQ(a.parameters.sample_density, b.parameters.sample_density);
  EXPECT_EQ(a.num_samples, b.num_samples);
  ASSERT_EQ(a.filter_reports.size(), b.filter_reports.size());
  for (std::size_t i = 0; i < a.filter_reports.size(); ++i) {
    EXPECT_EQ(a.filter_reports[i].name, b.filter_reports[i].name);
    EXPECT_EQ(a.filter_reports[i].removed, b.filter_reports[i].removed);
  }
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.curvature, b.curvature);
  EXPECT_EQ(a.geometry.center_of_mass, b.geometry.center_of_mass);
  EXPECT_EQ(a.geometry.rho, b.geometry.rho);
  EXPECT_EQ(a.geometry.volume, b.geometry.volume);
  EXPECT_EQ(a.geometry.closed, b.geometry.closed);
  EXPECT_EQ(a.geometry.hull_vertices, b.geometry.hull_vertices);
  EXPECT_EQ(a.geometry.hull_faces, b.geometry.hull_faces);
  EXPECT_EQ(a.geometry.mesh_vertices, b.geometry.mesh_vertices);
  EXPECT_EQ(a.geometry.mesh_triangles, b.geometry.mesh_triangles);
  ASSERT_EQ(a.levels.size(), b.levels.size());
  for (std::size_t l = 0; l < a.levels.size(); ++l) {
    ASSERT_EQ(a.levels[l].size(), b.levels[l].size());
    for (std::size_t i = 0; i < a.levels[l].size(); ++i) {
      const HierarchyNode &x = a.levels[l][i], &y = b.levels[l][i];
      EXPECT_EQ(x.contact_begin, y.contact_begin);
      EXPECT_EQ(x.contact_count, y.contact_count);
      EXPECT_EQ(x.child_begin, y.child_begin);
      EXPECT_EQ(x.child_count, y.child_count);
      EXPECT_EQ(x.representative, y.representative);
      EXPECT_EQ(x.mean_normal, y.mean_normal);
    }
  }
}

void expectLoadError(const std::filesystem::path& path, const std::string& problem) {
  test::expectErrorMentioning<DatabaseError>([&] { loadObjectDatabase(path); },
                                             {path.string(), problem});
}

TEST(ObjectDatabase, RoundTripKeepsEveryField) {
  TempDir dir;
  saveObjectDatabase(sample(), dir / "torus.h5");
  expectSame(sample(), loadObjectDatabase(dir / "torus.h5"));
}

TEST(ObjectDatabase, SaveLeavesNoTemporaryFilesAndReplacesAtomically) {
  TempDir dir;
  saveObjectDatabase(sample(), dir / "torus.h5");
  saveObjectDatabase(sample(), dir / "torus.h5");
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir.path()))
    ++files;
  EXPECT_EQ(files, 1u);
}

TEST(ObjectDatabase, InvalidContentIsNotWrittenAndTheOldFileSurvives) {
  TempDir dir;
  saveObjectDatabase(sample(), dir / "torus.h5");
  const std::string before = test::readBytes(dir / "torus.h5");
  ObjectDatabase broken = sample();
  broken.levels[1][3].contact_count += 1;  // children no longer partition
  EXPECT_THROW(saveObjectDatabase(broken, dir / "torus.h5"), DatabaseError);
  EXPECT_EQ(test::readBytes(dir / "torus.h5"), before);
  EXPECT_THROW(saveObjectDatabase(sample(), dir / "no" / "such" / "dir.h5"), DatabaseError);
}

TEST(ObjectDatabase, ValidationNamesTheViolation) {
  ObjectDatabase db = sample();
  db.normals(5, 0) += 0.5;
  try {
    validateObjectDatabase(db, "x");
    FAIL();
  } catch (const DatabaseError& e) {
    EXPECT_NE(std::string(e.what()).find("normals row 5"), std::string::npos) << e.what();
  }
  db = sample();
  db.levels[2][0].representative = db.levels[2][0].contact_begin + db.levels[2][0].contact_count;
  EXPECT_THROW(validateObjectDatabase(db, "x"), DatabaseError);
  db = sample();
  db.levels[0].pop_back();
  EXPECT_THROW(validateObjectDatabase(db, "x"), DatabaseError);
}

TEST(ObjectDatabase, MissingEmptyAndForeignFilesAreRejected) {
  TempDir dir;
  expectLoadError(dir / "missing.h5", "no such file");
  test::writeText(dir / "empty.h5", "");
  expectLoadError(dir / "empty.h5", "not an HDF5 file");
  test::writeText(dir / "text.h5", "this is not a database\n");
  expectLoadError(dir / "text.h5", "not an HDF5 file");
  test::writeForeignHdf5(dir / "foreign.h5");
  expectLoadError(dir / "foreign.h5", "not an HFTS object database");
}

TEST(ObjectDatabase, NewerFormatVersionIsRejected) {
  TempDir dir;
  saveObjectDatabase(sample(), dir / "v.h5");
  test::setFormatVersion(dir / "v.h5", 99);
  expectLoadError(dir / "v.h5", "format version 99 is not supported");
}

TEST(ObjectDatabase, VersionOneIsRejectedBeforeItsStringsAreRead) {
  TempDir dir;
  saveObjectDatabase(sample(), dir / "v1.h5");
  test::setFormatVersion(dir / "v1.h5", 1);
  test::setVariableLengthString(dir / "v1.h5", "/", "format", "hfts-object-database");
  test::expectErrorMentioning<DatabaseError>(
      [&] { loadObjectDatabase(dir / "v1.h5"); },
      {"format version 1 is not supported", "reads version 2", "hfts-preprocess MESH -o DIR"});
}

TEST(ObjectDatabase, VariableLengthStringsAreNotRead) {
  // They live in HDF5's global heap, which has no checksum (see
  // docs/database.md, version 2).
  for (const char* object : {"/", "/parameters"}) {
    SCOPED_TRACE(object);
    TempDir dir;
    saveObjectDatabase(sample(), dir / "vl.h5");
    const std::string name = std::string(object) == "/" ? "name" : "filters";
    test::setVariableLengthString(dir / "vl.h5", object, name, "x");
    expectLoadError(dir / "vl.h5", "attribute '" + name + "' is not a fixed-length string");
  }
}

TEST(ObjectDatabase, StringsRoundTripAtAnyLengthUpToTheLimit) {
  TempDir dir;
  ObjectDatabase db = sample();
  for (const std::size_t length : {std::size_t{0}, std::size_t{1}, std::size_t{65535}}) {
    db.source_mesh = std::string(length, 'm');
    saveObjectDatabase(db, dir / "s.h5");
    EXPECT_EQ(loadObjectDatabase(dir / "s.h5").source_mesh, db.source_mesh);
  }
  db.source_mesh = std::string(65536, 'm');
  test::expectErrorMentioning<DatabaseError>([&] { saveObjectDatabase(db, dir / "s.h5"); },
                                             {"source_mesh", "longer than 65536 bytes"});
}

TEST(ObjectDatabase, TruncatedFilesAreRejected) {
  TempDir dir;
  saveObjectDatabase(sample(), dir / "full.h5");
  test::expectTruncationIsRejected<DatabaseError>(
      test::readBytes(dir / "full.h5"), dir / "cut.h5",
      [](const std::filesystem::path& p) { loadObjectDatabase(p); });
}

TEST(ObjectDatabase, BitFlipsAreDetectedOrHarmless) {
  TempDir dir;
  saveObjectDatabase(sample(), dir / "full.h5");
  const int detected = test::countDetectedBitFlips<DatabaseError>(
      test::readBytes(dir / "full.h5"), dir / "flip.h5", 400,
      [](const std::filesystem::path& p) { expectSame(loadObjectDatabase(p), sample()); });
  EXPECT_GT(detected, 100);  // most of the file is checksummed data
  // Every HDF5 object the failed loads opened was closed again: what
  // LeakSanitizer reports after this test is libhdf5's own (see
  // tests/sanitizers/lsan.supp).
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
}

TEST(AtomicFile, WritesAndReplaces) {
  TempDir dir;
  writeFileAtomically(dir / "f.txt", "one");
  writeFileAtomically(dir / "f.txt", "two");
  EXPECT_EQ(test::readBytes(dir / "f.txt"), "two");
  EXPECT_THROW(writeFileAtomically(dir / "missing" / "f.txt", "x"), std::runtime_error);
}

}  // namespace
}  // namespace hfts::db
