// A mesh file through loadMesh (assimp, then the project's checks), in the
// formats the project documents and bundles: the first byte picks STL, PLY,
// OBJ or DAE (the file's extension, which chooses assimp's importer), the
// rest is the file. A bad mesh must throw MeshError.

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_files.h"
#include "hfts_db/triangle_mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hfts;
  static const std::array<std::string, 4> kExtensions = {".stl", ".ply", ".obj", ".dae"};
  if (size < 1) return -1;
  const std::string& extension = kExtensions[data[0] % kExtensions.size()];
  fuzz::ScratchFile file("mesh", extension);
  try {
    // assimp loops forever on some files (in its child process): 1 s,
    // well below the fuzzer's -timeout, makes that a MeshError.
    const LoadedMesh loaded =
        loadMesh(file.write(data + 1, size - 1), 1.0,
                 IsolationLimits{std::chrono::seconds(1), std::size_t{1} << 30});
    analyzeTopology(loaded.mesh);
    surfaceArea(loaded.mesh);
  } catch (const MeshError&) {
  }
  return 0;
}
