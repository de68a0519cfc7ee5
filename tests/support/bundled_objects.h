#pragma once
// Databases of the bundled objects, built once per test program (a few
// seconds for all of them).

#include <map>
#include <string>

#include "preprocess/database_builder.h"
#include "test_meshes.h"

namespace hfts::test {

/// What the shared fixtures are built with: the defaults but a coarse
/// distance grid (8 mm). Every test process builds its fixtures again, and
/// the default grid would take most of that time; tests of the grid itself
/// build their own.
inline db::BuildParameters fixtureParameters() {
  db::BuildParameters params;
  params.distance_grid_spacing = 0.008;
  return params;
}

inline const std::map<std::string, db::ObjectDatabase>& bundledObjects() {
  static const std::map<std::string, db::ObjectDatabase> all = [] {
    std::map<std::string, db::ObjectDatabase> out;
    for (const auto& entry : std::filesystem::directory_iterator(bundledMeshDir())) {
      auto database =
          preprocess::buildObjectDatabaseFromFile(entry.path(), fixtureParameters()).database;
      out.emplace(database.name, std::move(database));
    }
    return out;
  }();
  return all;
}

}  // namespace hfts::test
