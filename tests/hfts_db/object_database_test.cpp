#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <vector>

#include "file_corruption.h"
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
    params.distance_grid_spacing = 0.006;  // 17 000 nodes: a small file, quick bit flips
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
  EXPECT_EQ(a.geometry.center_of_mass_method, b.geometry.center_of_mass_method);
  EXPECT_EQ(a.geometry.hull_vertices, b.geometry.hull_vertices);
  EXPECT_EQ(a.geometry.hull_faces, b.geometry.hull_faces);
  EXPECT_EQ(a.geometry.mesh_vertices, b.geometry.mesh_vertices);
  EXPECT_EQ(a.geometry.mesh_triangles, b.geometry.mesh_triangles);
  EXPECT_EQ(a.parameters.distance_grid_spacing, b.parameters.distance_grid_spacing);
  EXPECT_EQ(a.parameters.distance_grid_margin, b.parameters.distance_grid_margin);
  EXPECT_EQ(a.density, b.density);
  EXPECT_EQ(a.parameters.convex_parts_max, b.parameters.convex_parts_max);
  EXPECT_EQ(a.parameters.convex_parts_tolerance, b.parameters.convex_parts_tolerance);
  ASSERT_EQ(a.geometry.convex_parts.size(), b.geometry.convex_parts.size());
  for (std::size_t i = 0; i < a.geometry.convex_parts.size(); ++i) {
    EXPECT_EQ(a.geometry.convex_parts[i].vertices, b.geometry.convex_parts[i].vertices);
    EXPECT_EQ(a.geometry.convex_parts[i].faces, b.geometry.convex_parts[i].faces);
  }
  const DistanceGrid &ga = a.geometry.distance_grid, &gb = b.geometry.distance_grid;
  EXPECT_EQ(ga.origin, gb.origin);
  EXPECT_EQ(ga.spacing, gb.spacing);
  EXPECT_EQ(ga.dims, gb.dims);
  EXPECT_EQ(ga.is_signed, gb.is_signed);
  EXPECT_EQ(ga.boundary_min, gb.boundary_min);
  EXPECT_TRUE(ga.values == gb.values);  // not EXPECT_EQ: it would print 1 MB
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

void expectInvalid(const ObjectDatabase& db, const std::string& problem) {
  test::expectErrorMentioning<DatabaseError>([&] { validateObjectDatabase(db, "x"); },
                                             {"x: ", problem});
}

TEST(ObjectDatabase, DistanceGridViolationsNameTheField) {
  ObjectDatabase db = sample();
  db.geometry.distance_grid.dims[1] = 1;
  expectInvalid(db, "distance_grid.dims must be at least 2");
  db = sample();
  db.geometry.distance_grid.spacing = 0.0;
  expectInvalid(db, "distance_grid.spacing must be positive and finite");
  db = sample();
  db.geometry.distance_grid.origin.y() = std::nan("");
  expectInvalid(db, "distance_grid.origin holds non-finite values");
  db = sample();
  db.geometry.distance_grid.values.pop_back();
  expectInvalid(db, "distance_grid.values holds");
  db = sample();
  db.geometry.distance_grid.values[7] = std::numeric_limits<float>::infinity();
  expectInvalid(db, "distance_grid.values holds non-finite values");
  db = sample();
  db.geometry.distance_grid.origin.z() = db.geometry.bbox_min.z() + 1e-4;
  expectInvalid(db, "distance_grid does not cover the bounding box");
  db = sample();
  db.geometry.distance_grid.is_signed = !db.geometry.closed;
  expectInvalid(db, "distance_grid.signed must equal closed");
  db = sample();
  db.geometry.distance_grid.boundary_min += 1e-3f;
  expectInvalid(db, "distance_grid.boundary_min exceeds the smallest value on the grid's faces");
  db = sample();
  db.geometry.distance_grid = {};
  expectInvalid(db, "distance_grid.dims");
}

TEST(ObjectDatabase, EveryDatabaseHasASignedGridOfItsClosedMesh) {
  const ObjectDatabase& db = sample();
  const DistanceGrid& grid = db.geometry.distance_grid;
  ASSERT_TRUE(db.geometry.closed);  // the torus: tube radius 1.5 cm, hole radius 3.5 cm
  EXPECT_TRUE(grid.is_signed);
  EXPECT_EQ(grid.spacing, 0.006);
  const double slack = std::sqrt(3.0) * grid.spacing;
  EXPECT_GT(grid.lowerBound(db.geometry.center_of_mass), 0.035 - slack);
  const Eigen::Vector3d inTube =
      db.positions.row(0).transpose() - 0.012 * db.normals.row(0).transpose();
  EXPECT_LT(grid.lowerBound(inTube), -0.012 + slack);
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
      {"format version 1 is not supported", "reads version 4", "hfts-preprocess MESH -o DIR"});
}

/// The sample saved as `name`, then made a file of an older version:
/// `links` and `attributes` ({group, name}) removed, the version set.
std::filesystem::path olderVersion(
    const TempDir& dir, const std::string& name, int version, const std::vector<std::string>& links,
    const std::vector<std::pair<std::string, std::string>>& attributes) {
  saveObjectDatabase(sample(), dir / name);
  const hid_t file = H5Fopen((dir / name).c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  for (const std::string& link : links) H5Ldelete(file, link.c_str(), H5P_DEFAULT);
  for (const auto& [group, attribute] : attributes) {
    const hid_t g = H5Gopen2(file, group.c_str(), H5P_DEFAULT);
    H5Adelete(g, attribute.c_str());
    H5Gclose(g);
  }
  H5Fclose(file);
  test::setFormatVersion(dir / name, version);
  return dir / name;
}

void expectRebuildAsked(const std::filesystem::path& path, int version) {
  test::expectErrorMentioning<DatabaseError>(
      [&] { loadObjectDatabase(path); },
      {path.string(), "format version " + std::to_string(version) + " is not supported",
       "reads version 4", "rebuild it with hfts-preprocess MESH -o DIR"});
}

TEST(ObjectDatabase, VersionTwoIsRejectedNamingTheCommandThatRebuildsIt) {
  // A version-2 file: no distance grid, no grid parameters.
  TempDir dir;
  expectRebuildAsked(olderVersion(dir, "v2.h5", 2, {"distance_grid", "convex_parts"},
                                  {{"parameters", "distance_grid_spacing"},
                                   {"parameters", "distance_grid_margin"}}),
                     2);
}

TEST(ObjectDatabase, VersionThreeIsRejectedNamingTheCommandThatRebuildsIt) {
  // A version-3 file: no convex parts, no density, no decomposition
  // parameters. The physics check needs the parts, so it is rebuilt, not
  // read with the hull in their place.
  TempDir dir;
  expectRebuildAsked(olderVersion(dir, "v3.h5", 3, {"convex_parts"},
                                  {{"parameters", "convex_parts_max"},
                                   {"parameters", "convex_parts_tolerance"},
                                   {"object", "density"}}),
                     3);
}

TEST(ObjectDatabase, ConvexPartsCoverTheSolidAndTheDensityIsWaters) {
  const ObjectDatabase& db = sample();
  EXPECT_EQ(db.density, 1000.0);
  ASSERT_GT(db.geometry.convex_parts.size(), 1u);  // the torus is not convex
  double volume = 0.0;
  for (const ConvexPiece& part : db.geometry.convex_parts)
    volume += solidProperties(TriangleMesh{part.vertices, part.faces}).volume;
  EXPECT_GE(volume, db.geometry.volume * (1 - 1e-9));
  EXPECT_LE(volume, db.geometry.volume * (1 + db.parameters.convex_parts_tolerance));
}

TEST(ObjectDatabase, ConvexPartViolationsNameThePartAndTheProblem) {
  const ObjectDatabase& good = sample();
  ObjectDatabase db = good;
  db.geometry.convex_parts.clear();
  expectInvalid(db, "convex_parts must hold 1 to 1024 parts");
  db = good;
  Faces3& faces = db.geometry.convex_parts[1].faces;
  faces.conservativeResize(faces.rows() - 1, 3);
  expectInvalid(db, "convex part 1 is not a closed, consistently wound surface");
  db = good;
  db.geometry.convex_parts[0].faces.col(1).swap(db.geometry.convex_parts[0].faces.col(2));
  expectInvalid(db, "convex part 0 is wound inward");
  db = good;
  {
    // A corner pushed to the centroid makes a dent.
    ConvexPiece& part = db.geometry.convex_parts[2];
    const Eigen::RowVector3d centroid = part.vertices.colwise().mean();
    part.vertices.row(0) = 0.5 * (part.vertices.row(0) + centroid);
  }
  expectInvalid(db, "convex part 2 is not convex");
  db = good;
  db.geometry.convex_parts[0].vertices *= 1e-3;  // convex, closed, almost no volume
  expectInvalid(db, "convex part 0 holds less than the least volume of a part");
  db = good;
  db.geometry.convex_parts[0].vertices.col(2).array() += 1.0;
  expectInvalid(db, "convex part 0 reaches outside the bounding box");
  db = good;
  db.geometry.convex_parts[3].vertices(0, 0) = std::nan("");
  expectInvalid(db, "convex part 3 vertices holds non-finite values");
  db = good;
  db.geometry.convex_parts.push_back(db.geometry.convex_parts[0]);
  db.geometry.convex_parts.back().faces(0, 0) = 100000;
  expectInvalid(db, "convex part " + std::to_string(good.geometry.convex_parts.size()) +
                        " faces index a vertex that does not exist");
}

TEST(ObjectDatabase, DensityOutsideTenTo25000IsRejected) {
  ObjectDatabase db = sample();
  for (double density : {0.0, 9.9, 25001.0, std::nan(""), -1000.0}) {
    db.density = density;
    expectInvalid(db, "density must be in");
  }
  db.density = 7850.0;
  EXPECT_NO_THROW(validateObjectDatabase(db, "x"));
}

/// Deletes attribute `name` of group `group` in a database file.
void deleteAttribute(const std::filesystem::path& path, const char* group, const char* name) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hid_t g = H5Gopen2(file, group, H5P_DEFAULT);
  H5Adelete(g, name);
  H5Gclose(g);
  H5Fclose(file);
}

TEST(ObjectDatabase, AFileWithoutTheCentreOfMassMethodIsRejectedNamingTheAttribute) {
  // Version 4 requires it: a file without it was not written by this version.
  TempDir dir;
  saveObjectDatabase(sample(), dir / "old.h5");
  deleteAttribute(dir / "old.h5", "object", "center_of_mass_method");
  try {
    loadObjectDatabase(dir / "old.h5");
    FAIL() << "a file without center_of_mass_method was loaded";
  } catch (const std::exception& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("missing attribute 'center_of_mass_method'"));
  }
}

TEST(ObjectDatabase, AnUnknownCentreOfMassMethodIsRejectedByName) {
  TempDir dir;
  saveObjectDatabase(sample(), dir / "odd.h5");
  deleteAttribute(dir / "odd.h5", "object", "center_of_mass_method");
  {
    const hid_t file = H5Fopen((dir / "odd.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    const hid_t g = H5Gopen2(file, "object", H5P_DEFAULT);
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, 8);
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t attribute =
        H5Acreate2(g, "center_of_mass_method", type, space, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(attribute, type, "guessed");
    H5Aclose(attribute);
    H5Sclose(space);
    H5Tclose(type);
    H5Gclose(g);
    H5Fclose(file);
  }
  test::expectErrorMentioning<DatabaseError>(
      [&] { loadObjectDatabase(dir / "odd.h5"); },
      {(dir / "odd.h5").string(), "'guessed'", "center_of_mass_method"});
}

TEST(ObjectDatabase, DistanceGridValuesStoredAsDoublesAreRejected) {
  // Converting f64 to f32 rounds to nearest, which could round a distance up.
  TempDir dir;
  saveObjectDatabase(sample(), dir / "f64.h5");
  {
    const DistanceGrid& grid = sample().geometry.distance_grid;
    const std::vector<double> widened(grid.values.begin(), grid.values.end());
    const hsize_t shape[3] = {grid.dims[2], grid.dims[1], grid.dims[0]};
    const hid_t file = H5Fopen((dir / "f64.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    H5Ldelete(file, "distance_grid/values", H5P_DEFAULT);
    const hid_t space = H5Screate_simple(3, shape, nullptr);
    const hid_t set = H5Dcreate2(file, "distance_grid/values", H5T_IEEE_F64LE, space, H5P_DEFAULT,
                                 H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, widened.data());
    H5Dclose(set);
    H5Sclose(space);
    H5Fclose(file);
  }
  expectLoadError(dir / "f64.h5", "dataset 'values' must hold 32-bit elements");
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

}  // namespace
}  // namespace hfts::db
