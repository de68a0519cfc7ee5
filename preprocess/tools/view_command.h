#pragma once
// hfts-preprocess CLOUD --viewpoint X,Y,Z -o DIR: the database of an
// object seen from one side (docs/point_clouds.md#objects-from-a-partial-view).

#include <string>

#include "hfts_db/object_database.h"
#include "preprocess/partial_view.h"

namespace hfts::preprocess {

/// Reads the segmented cloud (PCD or PLY points, metres after
/// params.scale), builds its database into DIR/<stem>.h5 and prints the
/// build's summary line; warnings go to standard error unless `quiet`.
/// Returns 0, or 1 when the build failed (the reason on standard error).
int viewCommand(const std::string& cloud, const std::string& outDir,
                const db::BuildParameters& params, double density, const ViewOptions& view,
                bool quiet);

}  // namespace hfts::preprocess
