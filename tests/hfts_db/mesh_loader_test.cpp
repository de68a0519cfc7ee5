#include <gtest/gtest.h>

#include "hfts_db/triangle_mesh.h"
#include "test_meshes.h"

namespace hfts {
namespace {

using test::TempDir;

void expectUnitCube(const LoadedMesh& loaded, double size) {
  EXPECT_EQ(loaded.mesh.vertices.rows(), 8);
  EXPECT_EQ(loaded.mesh.triangles.rows(), 12);
  EXPECT_TRUE(loaded.topology.closed());
  EXPECT_TRUE(loaded.warnings.empty());
  EXPECT_NEAR(surfaceArea(loaded.mesh), 6 * size * size, 1e-7);
  const Eigen::RowVector3d extent =
      loaded.mesh.vertices.colwise().maxCoeff() - loaded.mesh.vertices.colwise().minCoeff();
  EXPECT_NEAR(extent.maxCoeff(), size, 1e-7);
}

TEST(MeshLoader, ReadsEveryRequiredFormatAsAClosedCube) {
  TempDir dir;
  const TriangleMesh cube = test::cube(0.1);
  test::writeBinaryStl(dir / "binary.stl", cube);
  test::writeAsciiStl(dir / "ascii.stl", cube);
  test::writeAsciiPly(dir / "cube.ply", cube);
  test::writeObj(dir / "cube.obj", cube);
  test::writeCollada(dir / "cube.dae", cube);
  for (const char* name : {"binary.stl", "ascii.stl", "cube.ply", "cube.obj", "cube.dae"}) {
    SCOPED_TRACE(name);
    expectUnitCube(loadMesh(dir / name), 0.1);
  }
}

TEST(MeshLoader, ScaleConvertsMillimetres) {
  TempDir dir;
  test::writeBinaryStl(dir / "mm.stl", test::cube(100.0));
  expectUnitCube(loadMesh(dir / "mm.stl", 0.001), 0.1);
}

TEST(MeshLoader, OpenMeshLoadsWithAWarning) {
  TempDir dir;
  TriangleMesh open = test::cube(0.1);
  open.triangles.conservativeResize(10, 3);  // drop the +x face
  test::writeObj(dir / "open.obj", open);
  const LoadedMesh loaded = loadMesh(dir / "open.obj");
  EXPECT_EQ(loaded.topology.boundary_edges, 4u);
  EXPECT_FALSE(loaded.topology.closed());
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find("4 boundary"), std::string::npos);
}

TEST(MeshLoader, NonManifoldMeshLoadsWithAWarning) {
  TempDir dir;
  // A fin: an extra triangle on an edge of the cube makes it non-manifold.
  TriangleMesh fin = test::cube(0.1);
  fin.vertices.conservativeResize(9, 3);
  fin.vertices.row(8) << 0.0, 0.0, 0.2;
  fin.triangles.conservativeResize(13, 3);
  fin.triangles.row(12) << 4, 5, 8;
  test::writeObj(dir / "fin.obj", fin);
  const LoadedMesh loaded = loadMesh(dir / "fin.obj");
  EXPECT_GT(loaded.topology.non_manifold_edges, 0u);
  bool warned = false;
  for (const std::string& w : loaded.warnings)
    warned |= w.find("non-manifold") != std::string::npos;
  EXPECT_TRUE(warned);
}

void expectMeshError(const std::filesystem::path& path, const std::string& problem) {
  test::expectErrorMentioning<MeshError>([&] { loadMesh(path); }, {path.string(), problem});
}

TEST(MeshLoader, BadFilesGiveClearErrorsNamingTheFile) {
  TempDir dir;
  expectMeshError(dir / "missing.stl", "no such file");
  test::writeText(dir / "empty.stl", "");
  expectMeshError(dir / "empty.stl", "empty");
  test::writeText(dir / "garbage.ply", std::string("\x01\x02garbage\xff\xfe", 12));
  expectMeshError(dir / "garbage.ply", "cannot be read");
  test::writeText(dir / "points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  expectMeshError(dir / "points.obj", "cannot be read");
  test::writeText(dir / "line.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
  expectMeshError(dir / "line.obj", "degenerate");
  test::writeObj(dir / "flat.obj", test::square(0.1, 0.0));
  expectMeshError(dir / "flat.obj", "one plane");
  test::writeText(dir / "nan.obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\n");
  expectMeshError(dir / "nan.obj", "");
}

// Files that made assimp 5.2.5 read out of bounds (found by the mesh
// fuzzer; tests/fuzz/third_party_crashes/): an error, not a crash.
TEST(MeshLoader, MalformedFilesThatCrashAssimpGiveErrors) {
  TempDir dir;
  // A face naming a vertex that does not exist (assimp's post-processing
  // read out of bounds; its ValidateDataStructure step now refuses it).
  test::writeText(dir / "bad_index.ply",
                  "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                  "property float y\nproperty float z\nelement face 2\n"
                  "property list uchar int vertex_indices\nend_header\n"
                  "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 4000000\n");
  expectMeshError(dir / "bad_index.ply", "cannot be read");
  // A binary PLY with a damaged header: assimp's importer itself reads
  // past its buffer (SEGV), now in the child process. The fuzzer's input
  // starts with a byte that picks the file type.
  const std::string input =
      test::readBytes(std::filesystem::path(HFTS_SOURCE_DIR) /
                      "tests/fuzz/corpus/mesh/regression_assimp_ply_importer_segv");
  ASSERT_GT(input.size(), 1u);
  const std::filesystem::path crash = dir / "importer_segv.ply";
  test::writeText(crash, input.substr(1));
  expectMeshError(crash, "assimp");
}

// A binary PLY on which assimp 5.2.5 reads the file forever (mesh
// fuzzer): the import is stopped at its time limit.
TEST(MeshLoader, AnImportThatNeverEndsIsStoppedAtTheTimeLimit) {
  TempDir dir;
  const std::string input =
      test::readBytes(std::filesystem::path(HFTS_SOURCE_DIR) /
                      "tests/fuzz/corpus/mesh/regression_assimp_ply_endless_loop");
  ASSERT_GT(input.size(), 1u);
  test::writeText(dir / "endless.ply", input.substr(1));
  IsolationLimits limits;
  limits.time = std::chrono::seconds(2);
  test::expectErrorMentioning<MeshError>([&] { loadMesh(dir / "endless.ply", 1.0, limits); },
                                         {"endless.ply", "did not finish within 2 s"});
}

TEST(MeshLoader, DefaultImportLimitsGrowWithTheFile) {
  EXPECT_EQ(meshImportLimits(0).time, std::chrono::seconds(60));
  EXPECT_EQ(meshImportLimits(std::uintmax_t{100} << 20).time, std::chrono::seconds(160));
  EXPECT_EQ(meshImportLimits(std::uintmax_t{1} << 30).extra_memory_bytes,
            (std::size_t{2} << 30) + (std::size_t{64} << 30));
}

TEST(MeshLoader, RejectsANonPositiveScale) {
  TempDir dir;
  test::writeBinaryStl(dir / "cube.stl", test::cube(0.1));
  EXPECT_THROW(loadMesh(dir / "cube.stl", 0.0), MeshError);
  EXPECT_THROW(loadMesh(dir / "cube.stl", -1.0), MeshError);
}

TEST(MeshChecks, SanitizeDropsZeroAreaTrianglesAndRejectsNonFinite) {
  TriangleMesh mesh = test::cube(0.1);
  mesh.triangles.conservativeResize(13, 3);
  mesh.triangles.row(12) << 0, 0, 1;
  EXPECT_EQ(sanitizeMesh(mesh, "m"), 1u);
  EXPECT_EQ(mesh.triangles.rows(), 12);
  mesh.vertices(0, 0) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(sanitizeMesh(mesh, "m"), MeshError);
}

TEST(MeshChecks, InconsistentWindingIsDetected) {
  TriangleMesh mesh = test::cube(0.1);
  mesh.triangles.row(0) = mesh.triangles.row(0).reverse().eval();
  const MeshTopology t = analyzeTopology(mesh);
  EXPECT_EQ(t.inconsistent_edges, 3u);
  EXPECT_FALSE(t.closed());
}

TEST(SolidProperties, InvertedWindingGivesThePositiveVolume) {
  const SolidProperties s = solidProperties(test::flipped(test::cube(0.2)));
  EXPECT_NEAR(s.volume, 0.008, 1e-12);
  EXPECT_LT(s.centroid.norm(), 1e-12);
}

}  // namespace
}  // namespace hfts
