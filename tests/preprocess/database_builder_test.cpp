#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <thread>
#include <tuple>

#include "bundled_objects.h"
#include "core/invalid_argument.h"
#include "preprocess/database_builder.h"
#include "test_meshes.h"

namespace hfts::preprocess {
namespace {

using test::TempDir;

using test::bundledMeshes;

TEST(DatabaseBuilder, AtLeastEightObjectsAreBundled) {
  EXPECT_GE(bundledMeshes().size(), 8u);
}

TEST(DatabaseBuilder, EveryBundledObjectGivesAValid20_4_4Hierarchy) {
  for (const auto& mesh : bundledMeshes()) {
    SCOPED_TRACE(mesh.filename().string());
    const BuildResult r = buildObjectDatabaseFromFile(mesh, db::BuildParameters{});
    const db::ObjectDatabase& db = r.database;
    EXPECT_NO_THROW(db::validateObjectDatabase(db, mesh.string()));  // exact partition etc.
    EXPECT_GT(db.numContacts(), 1000u);
    EXPECT_EQ(db.levels[0].size(), 20u);
    EXPECT_EQ(db.levels[1].size(), 80u);
    EXPECT_GT(db.levels[2].size(), 250u);  // small clusters may split in fewer
    EXPECT_TRUE(db.geometry.closed);
    EXPECT_EQ(db.geometry.center_of_mass_method, db::CenterOfMassMethod::kClosedMesh);
    // Realistic sizes for the hand: 4-20 cm.
    const double size = (db.geometry.bbox_max - db.geometry.bbox_min).maxCoeff();
    EXPECT_GE(size, 0.04);
    EXPECT_LE(size, 0.20 + 1e-6);
    EXPECT_EQ(db.name, mesh.stem().string());
    EXPECT_EQ(db.source_sha256.size(), 64u);
    EXPECT_EQ(
        db.num_samples, db.numContacts() + [&] {
          std::uint64_t removed = 0;
          for (const auto& f : db.filter_reports) removed += f.removed;
          return removed;
        }());
  }
}

TEST(DatabaseBuilder, ConvexObjectsHaveOutwardNormals) {
  for (const char* name : {"box.stl", "cylinder.stl"}) {
    const BuildResult r =
        buildObjectDatabaseFromFile(test::bundledMeshDir() / name, db::BuildParameters{});
    const db::ObjectDatabase& db = r.database;
    for (Eigen::Index i = 0; i < db.positions.rows(); ++i)
      EXPECT_GT(db.normals.row(i).dot(db.positions.row(i) - db.geometry.center_of_mass.transpose()),
                0.0);
  }
}

TEST(DatabaseBuilder, AClosedMeshWoundInwardsIsTurnedOutwardsWithAWarning) {
  // Wound inwards, every signed distance would have its inside out.
  const TriangleMesh outward = test::cube(0.06);
  const BuildResult turned = buildObjectDatabase(test::flipped(outward), true,
                                                 test::fixtureParameters(), "inside-out cube");
  ASSERT_EQ(turned.warnings.size(), 1u);
  EXPECT_NE(turned.warnings[0].find("inside-out cube: the faces are wound inwards"),
            std::string::npos)
      << turned.warnings[0];
  const BuildResult same = buildObjectDatabase(outward, true, test::fixtureParameters(), "cube");
  EXPECT_TRUE(same.warnings.empty());
  EXPECT_EQ(turned.database.geometry.mesh_triangles, same.database.geometry.mesh_triangles);
  EXPECT_EQ(turned.database.geometry.distance_grid.values,
            same.database.geometry.distance_grid.values);
}

TEST(DatabaseBuilder, AScanWithAHoleIsDecomposedAsItsCappedSolid) {
  // An L of two blocks (the shape needs two convex parts), two triangles
  // of its top face missing, as a scan leaves it: the mesh bounds nothing,
  // its capped mesh does.
  TriangleMesh l = test::merged(test::block({0, 0, 0}, {0.08, 0.03, 0.03}),
                                test::block({0, 0, 0.03}, {0.03, 0.03, 0.08}));
  const double volume = 0.08 * 0.03 * 0.03 + 0.03 * 0.03 * 0.05;
  l.triangles.conservativeResize(l.triangles.rows() - 2, 3);
  const db::ObjectDatabase d =
      buildObjectDatabase(l, false, test::fixtureParameters(), "L").database;
  EXPECT_FALSE(d.geometry.closed);
  EXPECT_EQ(d.geometry.center_of_mass_method, db::CenterOfMassMethod::kRepairedMesh);
  ASSERT_GE(d.geometry.convex_parts.size(), 2u) << "not the hull alone";
  double parts = 0.0;
  for (const db::ConvexPiece& p : d.geometry.convex_parts)
    parts += solidProperties(TriangleMesh{p.vertices, p.faces}).volume;
  EXPECT_NEAR(parts, volume, 0.05 * volume);
}

TEST(DatabaseBuilder, SameInputAndParametersGiveIdenticalBytes) {
  // Sequential and concurrent builds of every bundled object, in one
  // process, must write the same bytes (CGAL's hull order depends on
  // memory addresses; the stored hull must not). With the fixtures' coarse
  // distance grid: the default one made this the slowest test of the suite.
  TempDir dir;
  db::BuildParameters params = test::fixtureParameters();
  params.convex_parts_max = 64;  // as deterministic as 1024 parts, 5 times faster for the vase
  const auto meshes = bundledMeshes();
  auto buildAll = [&](const std::string& suffix, bool concurrent) {
    std::vector<std::thread> threads;
    for (const auto& mesh : meshes) {
      auto job = [&dir, &params, mesh, suffix] {
        db::saveObjectDatabase(buildObjectDatabaseFromFile(mesh, params).database,
                               dir / (mesh.stem().string() + suffix));
      };
      if (concurrent)
        threads.emplace_back(job);
      else
        job();
    }
    for (auto& t : threads) t.join();
  };
  buildAll(".a.h5", false);
  buildAll(".b.h5", false);
  buildAll(".c.h5", true);
  for (const auto& mesh : meshes) {
    SCOPED_TRACE(mesh.filename().string());
    const std::string a = test::readBytes(dir / (mesh.stem().string() + ".a.h5"));
    ASSERT_GT(a.size(), 1000u);
    EXPECT_TRUE(a == test::readBytes(dir / (mesh.stem().string() + ".b.h5")));
    EXPECT_TRUE(a == test::readBytes(dir / (mesh.stem().string() + ".c.h5")));
  }
  db::BuildParameters other = params;
  other.seed = 2;
  db::saveObjectDatabase(buildObjectDatabaseFromFile(meshes[0], other).database, dir / "seed2.h5");
  EXPECT_FALSE(test::readBytes(dir / (meshes[0].stem().string() + ".a.h5")) ==
               test::readBytes(dir / "seed2.h5"));
}

TEST(DatabaseBuilder, InternalGeometryNeverProducesContacts) {
  // Hollow cube with a floating inner face: only the outer surface counts.
  const TriangleMesh mesh = test::merged(
      test::merged(test::cube(0.1), test::flipped(test::cube(0.05))), test::square(0.03, 0.0));
  const BuildResult r = buildObjectDatabase(mesh, false, {}, "hollow");
  for (Eigen::Index i = 0; i < r.database.positions.rows(); ++i)
    EXPECT_NEAR(r.database.positions.row(i).cwiseAbs().maxCoeff(), 0.05, 1e-9);
}

TEST(DatabaseBuilder, AMeshThatIsNotClosedSaysWhereItsCentreOfMassCameFrom) {
  const TriangleMesh cup = test::cup();
  TriangleMesh holed{cup.vertices, cup.triangles.topRows(cup.triangles.rows() - 1)};
  const BuildResult repaired = buildObjectDatabase(holed, false, {}, "mesh 'holed cup'");
  const BuildResult closed = buildObjectDatabase(cup, true, {}, "mesh 'cup'");
  EXPECT_TRUE(closed.warnings.empty());
  EXPECT_EQ(repaired.database.geometry.center_of_mass_method,
            db::CenterOfMassMethod::kRepairedMesh);
  EXPECT_LT(
      (repaired.database.geometry.center_of_mass - closed.database.geometry.center_of_mass).norm(),
      1e-9);
  EXPECT_NEAR(repaired.database.geometry.volume, closed.database.geometry.volume, 1e-12);
  ASSERT_EQ(repaired.warnings.size(), 1u);
  EXPECT_NE(repaired.warnings[0].find("mesh 'holed cup': the centre of mass is the volume "
                                      "centroid of the mesh with its boundary capped (1 boundary "
                                      "part"),
            std::string::npos)
      << repaired.warnings[0];

  // Two faces of a box meeting at an edge are a folded sheet: no solid.
  TriangleMesh sheet = test::cube(0.1);
  sheet.triangles.middleRows(2, 2) = sheet.triangles.middleRows(4, 2).eval();
  sheet.triangles.conservativeResize(4, 3);
  const BuildResult hull = buildObjectDatabase(sheet, false, {}, "mesh 'sheet'");
  EXPECT_EQ(hull.database.geometry.center_of_mass_method, db::CenterOfMassMethod::kConvexHull);
  EXPECT_EQ(hull.database.geometry.volume, 0.0);
  ASSERT_EQ(hull.warnings.size(), 1u);
  EXPECT_NE(hull.warnings[0].find("convex hull's centroid, a last resort"), std::string::npos)
      << hull.warnings[0];
}

TEST(DatabaseBuilder, StoresTheFilterScalesItResolvedFromThePad) {
  db::BuildParameters params;
  params.pad_radius = 0.012;
  params.min_neighbours = 4;  // given: kept
  const db::BuildParameters& stored =
      buildObjectDatabase(test::cube(0.1), true, params, "cube").database.parameters;
  EXPECT_EQ(stored.pad_radius, 0.012);
  EXPECT_DOUBLE_EQ(stored.patch_radius, 0.006);
  EXPECT_EQ(stored.min_neighbours, 4u);
}

TEST(DatabaseBuilder, ExplainsWhenFiltersLeaveNothing) {
  db::BuildParameters params;
  params.max_curvature = 0.0;
  params.patch_radius = 0.01;  // every patch of a 1 cm cube reaches an edge
  params.filters = {"curvature"};
  try {
    buildObjectDatabase(test::merged(test::cube(0.01), test::cube(0.01, {0.03, 0, 0})), true,
                        params, "tiny");
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("no contacts left"), std::string::npos) << e.what();
  }
}

TEST(DatabaseBuilder, AllFiltersCanBeSwitchedOff) {
  db::BuildParameters params;
  params.filters = {};
  const BuildResult r = buildObjectDatabase(test::cube(0.1), true, params, "cube");
  EXPECT_TRUE(r.database.filter_reports.empty());
  EXPECT_EQ(r.database.numContacts(), r.database.num_samples);
  TempDir dir;
  db::saveObjectDatabase(r.database, dir / "cube.h5");
  EXPECT_TRUE(db::loadObjectDatabase(dir / "cube.h5").filter_reports.empty());
}

TEST(DatabaseBuilder, RejectsBadParametersByName) {
  db::BuildParameters params;
  params.patch_radius = -1;
  EXPECT_THROW(checkBuildParameters(params), std::invalid_argument);
  params = {};
  params.pad_radius = 0;
  test::expectErrorMentioning<InvalidArgument>([&] { checkBuildParameters(params); },
                                               {"pad_radius"});
  params = {};
  params.branching = {20, 0};
  EXPECT_THROW(checkBuildParameters(params), std::invalid_argument);
  params = {};
  params.filters = {"magic"};
  EXPECT_THROW(checkBuildParameters(params), std::invalid_argument);
}

TEST(DatabaseBuilder, RejectsBadDistanceGridParametersByName) {
  auto expectField = [](const db::BuildParameters& params, const std::string& field) {
    try {
      checkBuildParameters(params);
      ADD_FAILURE() << "no error for " << field;
    } catch (const InvalidArgument& e) {
      EXPECT_EQ(e.field(), field) << e.what();
    }
  };
  db::BuildParameters params;
  params.distance_grid_spacing = -0.001;
  expectField(params, "distance_grid_spacing");
  params = {};
  params.distance_grid_margin = std::nan("");
  expectField(params, "distance_grid_margin");
  // Too fine for the mesh: known only once the mesh is, still named by its parameter.
  params = {};
  params.distance_grid_spacing = 1e-5;
  try {
    buildObjectDatabase(test::cube(0.1), true, params, "cube");
    ADD_FAILURE() << "no error";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.field(), "distance_grid_spacing") << e.what();
  }
}

TEST(DatabaseBuilder, TheDistanceGridFollowsItsParameters) {
  db::BuildParameters params;
  params.distance_grid_spacing = 0.004;
  params.distance_grid_margin = 0.01;
  const BuildResult r = buildObjectDatabase(test::cube(0.1), true, params, "cube");
  const db::DistanceGrid& grid = r.database.geometry.distance_grid;
  EXPECT_EQ(grid.spacing, 0.004);
  EXPECT_TRUE(grid.is_signed);
  EXPECT_TRUE((grid.origin.array() <= -0.06).all()) << grid.origin.transpose();
  EXPECT_TRUE((grid.boxMax().array() >= 0.06).all()) << grid.boxMax().transpose();
  EXPECT_GT(grid.origin.x(), -0.06 - 0.004);  // the margin, not a node more
  EXPECT_GT(r.times.distance_grid, 0.0);
  EXPECT_LT(grid.lowerBound(Eigen::Vector3d::Zero()), -0.05 + 0.004 * std::sqrt(3.0));
}

TEST(DatabaseBuilder, TheConvexPartsFollowTheirParametersAndAreTimed) {
  const TriangleMesh torus = loadMesh(test::bundledMeshDir() / "torus.stl").mesh;
  db::BuildParameters params = test::fixtureParameters();
  params.convex_parts_max = 4;
  const BuildResult r = buildObjectDatabase(torus, true, params, "torus");
  EXPECT_EQ(r.database.geometry.convex_parts.size(), 4u);
  EXPECT_GT(r.times.convex_parts, 0.0);
  EXPECT_EQ(r.database.density, db::kDefaultDensity);
  // A convex object is one part, and its volume is the mesh's.
  const BuildResult cube = buildObjectDatabase(test::cube(0.1), true, params, "cube");
  EXPECT_EQ(cube.database.geometry.convex_parts.size(), 1u);
  EXPECT_NEAR(cube.database.geometry.volume, 0.001, 1e-15);
}

TEST(DatabaseBuilder, TheDensityIsTheSidecarsElseTheOneGivenElseWaters) {
  TempDir dir;
  test::writeBinaryStl(dir / "a.stl", test::cube(0.1));
  test::writeBinaryStl(dir / "b.stl", test::cube(0.1));
  test::writeText(dir / "b.json", "{\"density\": 2300}");
  const db::BuildParameters params = test::fixtureParameters();
  EXPECT_EQ(buildObjectDatabaseFromFile(dir / "a.stl", params).database.density, 1000.0);
  EXPECT_EQ(buildObjectDatabaseFromFile(dir / "a.stl", params, 700.0).database.density, 700.0);
  EXPECT_EQ(buildObjectDatabaseFromFile(dir / "b.stl", params, 700.0).database.density, 2300.0);
  test::expectErrorMentioning<InvalidArgument>(
      [&] { buildObjectDatabaseFromFile(dir / "a.stl", params, 5.0); },
      {"density: must be in [10, 25000] kg/m^3, got 5"});
  test::writeText(dir / "b.json", "{\"density\": -1}");
  test::expectErrorMentioning<InvalidArgument>(
      [&] { buildObjectDatabaseFromFile(dir / "b.stl", params); },
      {(dir / "b.json").string(), "density: must be in"});
}

TEST(DatabaseBuilder, RejectsBadConvexPartParametersByName) {
  for (const auto& [max, tolerance, field] :
       std::vector<std::tuple<std::uint32_t, double, std::string>>{
           {0, 0.04, "convex_parts_max"},
           {2000, 0.04, "convex_parts_max"},
           {64, 1.0, "convex_parts_tolerance"},
           {64, std::nan(""), "convex_parts_tolerance"}}) {
    db::BuildParameters params;
    params.convex_parts_max = max;
    params.convex_parts_tolerance = tolerance;
    test::expectErrorMentioning<InvalidArgument>([&] { checkBuildParameters(params); },
                                                 {field + ": must be in"});
  }
}

TEST(Sha256, MatchesAKnownDigest) {
  TempDir dir;
  test::writeText(dir / "abc", "abc");
  EXPECT_EQ(sha256File(dir / "abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

}  // namespace
}  // namespace hfts::preprocess
