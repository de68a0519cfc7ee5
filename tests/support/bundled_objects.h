#pragma once
// Databases of the bundled objects, built once per test program (about a
// second for all eight).

#include <map>
#include <string>

#include "preprocess/database_builder.h"
#include "test_meshes.h"

namespace hfts::test {

inline const std::map<std::string, db::ObjectDatabase>& bundledObjects() {
  static const std::map<std::string, db::ObjectDatabase> all = [] {
    std::map<std::string, db::ObjectDatabase> out;
    for (const auto& entry : std::filesystem::directory_iterator(bundledMeshDir())) {
      auto database = preprocess::buildObjectDatabaseFromFile(entry.path(), {}).database;
      out.emplace(database.name, std::move(database));
    }
    return out;
  }();
  return all;
}

}  // namespace hfts::test
