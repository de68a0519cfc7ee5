// An object database file (HDF5) through loadObjectDatabase, then what the
// planning world builds from a loaded one (collision mesh, HFTS space). A
// bad file must throw DatabaseError. Crashes inside libhdf5 are reported in
// docs of the fuzzing notes with their inputs kept.

#include <cstddef>
#include <cstdint>

#include "fuzz_files.h"
#include "grasp/hfts_space.h"
#include "hfts_db/object_database.h"
#include "robot/collision_checker.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hfts;
  static fuzz::ScratchFile file("object", ".h5");
  db::ObjectDatabase database;
  try {
    database = db::loadObjectDatabase(file.write(data, size));
  } catch (const db::DatabaseError&) {
    return 0;
  }
  const robot::CollisionMesh mesh(
      TriangleMesh{database.geometry.mesh_vertices, database.geometry.mesh_triangles});
  const grasp::HftsSpace space(database, 3);
  return 0;
}
