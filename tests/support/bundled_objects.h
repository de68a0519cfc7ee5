#pragma once
// Databases of the bundled objects, built once per ctest run (the
// test_fixtures test) or, outside ctest, once per test program.

#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include "preprocess/database_builder.h"
#include "test_meshes.h"

namespace hfts::test {

/// What the shared fixtures are built with: the defaults but a coarse
/// distance grid (8 mm); tests of the grid itself build their own.
inline db::BuildParameters fixtureParameters() {
  db::BuildParameters params;
  params.distance_grid_spacing = 0.008;
  return params;
}

/// The environment variable naming the directory of prebuilt fixtures.
inline constexpr const char* kFixtureDirVariable = "HFTS_TEST_FIXTURES";

/// Where a fixture directory holds the database of `mesh`.
inline std::filesystem::path fixtureFile(const std::filesystem::path& dir,
                                         const std::filesystem::path& mesh) {
  return dir / (mesh.stem().string() + ".h5");
}

/// The database of one bundled mesh, built from the mesh with
/// fixtureParameters().
inline db::ObjectDatabase buildBundledObject(const std::filesystem::path& mesh) {
  return preprocess::buildObjectDatabaseFromFile(mesh, fixtureParameters()).database;
}

/// buildBundledObject(mesh) as the tests get it. Under ctest it is read
/// from the directory in HFTS_TEST_FIXTURES, where the test_fixtures test
/// (build_test_fixtures) wrote it in the same run; a missing or unreadable
/// file there fails loudly. A test program run by hand builds it.
inline db::ObjectDatabase bundledObject(const std::filesystem::path& mesh) {
  if (const char* dir = std::getenv(kFixtureDirVariable); dir != nullptr && *dir != '\0')
    return db::loadObjectDatabase(fixtureFile(dir, mesh));
  return buildBundledObject(mesh);
}

inline const std::map<std::string, db::ObjectDatabase>& bundledObjects() {
  static const std::map<std::string, db::ObjectDatabase> all = [] {
    std::map<std::string, db::ObjectDatabase> out;
    for (const std::filesystem::path& mesh : bundledMeshes()) {
      auto database = bundledObject(mesh);
      out.emplace(database.name, std::move(database));
    }
    return out;
  }();
  return all;
}

}  // namespace hfts::test
