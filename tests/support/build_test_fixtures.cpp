// Builds the databases of every bundled mesh with the test fixtures'
// parameters into the directory given as the only argument, as
// <mesh stem>.h5 (each written atomically). ctest runs it once, as the
// test_fixtures test, before every test program that reads them.

#include <exception>
#include <filesystem>
#include <iostream>

#include "bundled_objects.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: build_test_fixtures OUTPUT_DIR\n";
    return 2;
  }
  try {
    const std::filesystem::path out = argv[1];
    std::filesystem::create_directories(out);
    int built = 0;
    for (const std::filesystem::path& mesh : hfts::test::bundledMeshes()) {
      hfts::db::saveObjectDatabase(hfts::test::buildBundledObject(mesh),
                                   hfts::test::fixtureFile(out, mesh));
      ++built;
    }
    std::cout << built << " fixture databases in " << out.string() << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "build_test_fixtures: " << e.what() << "\n";
    return 1;
  }
}
