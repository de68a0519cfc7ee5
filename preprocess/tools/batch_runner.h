#pragma once
// Building the databases of many meshes in parallel, with progress and a
// summary table.

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "hfts_db/object_database.h"
#include "preprocess/database_builder.h"

namespace hfts::preprocess {

struct BatchOutcome {
  std::filesystem::path mesh;
  std::string name;
  bool ok = false;
  std::string error;
  std::vector<std::string> warnings;
  std::size_t samples = 0;
  std::size_t contacts = 0;
  std::vector<std::size_t> nodes_per_level;
  std::size_t convex_parts = 0;
  double convex_parts_seconds = 0.0;  ///< the convex decomposition's share of `seconds`
  double seconds = 0.0;
};

/// `outcome` filled from a finished build (ok, its counts and warnings).
void describeBuild(const BuildResult& result, BatchOutcome& outcome);

/// The meshes to process: `input` itself if it is a file, else the files of
/// the directory (not recursive) with an extension assimp can import, sorted
/// by name; a sidecar (`.json`, object_sidecar.h) is never a mesh. Throws
/// std::runtime_error if `input` does not exist or a directory holds no
/// mesh.
std::vector<std::filesystem::path> collectMeshes(const std::filesystem::path& input);

/// Builds OUTDIR/<stem>.h5 for every mesh with `jobs` worker threads, of
/// `density` (kg/m^3) unless a mesh's sidecar says otherwise.
/// A failing mesh is reported in its outcome and does not stop the others.
/// Warnings and errors go to `log` as they happen; so does progress if
/// `showProgress` (a bar on a terminal, a line per object otherwise).
std::vector<BatchOutcome> runBatch(const std::vector<std::filesystem::path>& meshes,
                                   const std::filesystem::path& outDir,
                                   const db::BuildParameters& params, double density, unsigned jobs,
                                   std::ostream& log, bool logIsTerminal, bool showProgress);

/// The table printed at the end: object, contacts kept, nodes per level,
/// convex parts, the convex decomposition's time and the whole time.
void printSummaryTable(std::ostream& out, const std::vector<BatchOutcome>& outcomes);

}  // namespace hfts::preprocess
