#include "preprocess/object_sidecar.h"

#include <gtest/gtest.h>

#include "core/invalid_argument.h"
#include "test_meshes.h"

namespace hfts::preprocess {
namespace {

using test::TempDir;

TEST(ObjectSidecar, IsTheJsonFileOfTheMeshStemBesideIt) {
  EXPECT_EQ(sidecarPath("/objects/meshes/mug.ply"), "/objects/meshes/mug.json");
  EXPECT_EQ(sidecarPath("tin.can.stl"), "tin.can.json");
}

TEST(ObjectSidecar, NoneMeansNoKeys) {
  TempDir dir;
  EXPECT_FALSE(readSidecar(dir / "box.stl").density.has_value());
}

TEST(ObjectSidecar, GivesTheDensity) {
  TempDir dir;
  test::writeText(dir / "kettlebell.json", "{\"density\": 7200}");
  EXPECT_EQ(readSidecar(dir / "kettlebell.ply").density, 7200.0);
  test::writeText(dir / "foam.json", "{\"density\": 10}");  // the limits are allowed
  EXPECT_EQ(readSidecar(dir / "foam.obj").density, 10.0);
  EXPECT_EQ(readSidecar(test::bundledMeshDir() / "washer.obj").density, 7850.0);
}

TEST(ObjectSidecar, BadContentIsRejectedNamingTheFileAndTheKey) {
  TempDir dir;
  const std::string file = "sidecar '" + (dir / "box.json").string() + "'";
  for (const auto& [content, parts] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"{\"density\": 9.5}", {file + ": density: must be in [10, 25000] kg/m^3, got 9.5"}},
           {"{\"density\": 1e9}", {file + ": density: must be in [10, 25000]"}},
           {"{\"density\": \"steel\"}", {file + ": density: must be a number (kg/m^3)"}},
           {"{\"density\": null}", {file + ": density: must be a number"}},
           {"{\"mass\": 0.4}", {file + ": mass: unknown key (a sidecar may hold: density)"}},
           {"[7200]", {file + ": must be a JSON object"}},
           {"{\"density\": 7200", {file + ": is not valid JSON"}},
           {"", {file + ": is not valid JSON"}}}) {
    SCOPED_TRACE(content);
    test::writeText(dir / "box.json", content);
    test::expectErrorMentioning<InvalidArgument>([&] { readSidecar(dir / "box.stl"); }, parts);
  }
}

TEST(ObjectSidecar, CheckDensityNamesTheField) {
  EXPECT_NO_THROW(checkDensity(1000.0, "density"));
  for (double bad : {0.0, -1.0, 25000.5, std::nan(""), 1.0 / 0.0})
    test::expectErrorMentioning<InvalidArgument>([&] { checkDensity(bad, "density"); },
                                                 {"density: must be in [10, 25000] kg/m^3"});
}

}  // namespace
}  // namespace hfts::preprocess
