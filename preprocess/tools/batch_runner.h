#pragma once
// Building the databases of many meshes in parallel, with progress and a
// summary table.

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "hfts_db/object_database.h"

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
  double seconds = 0.0;
};

/// The meshes to process: `input` itself if it is a file, else the files of
/// the directory (not recursive) with an extension assimp can import, sorted
/// by name. Throws std::runtime_error if `input` does not exist or a
/// directory holds no mesh.
std::vector<std::filesystem::path> collectMeshes(const std::filesystem::path& input);

/// Builds OUTDIR/<stem>.h5 for every mesh with `jobs` worker threads.
/// A failing mesh is reported in its outcome and does not stop the others.
/// Warnings and errors go to `log` as they happen; so does progress if
/// `showProgress` (a bar on a terminal, a line per object otherwise).
std::vector<BatchOutcome> runBatch(const std::vector<std::filesystem::path>& meshes,
                                   const std::filesystem::path& outDir,
                                   const db::BuildParameters& params, unsigned jobs,
                                   std::ostream& log, bool logIsTerminal, bool showProgress);

/// The table printed at the end: object, contacts kept, nodes per level, time.
void printSummaryTable(std::ostream& out, const std::vector<BatchOutcome>& outcomes);

}  // namespace hfts::preprocess
