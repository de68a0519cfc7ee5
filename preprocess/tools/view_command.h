#pragma once
// hfts-preprocess CLOUD... --viewpoint X,Y,Z... -o DIR: the database of an
// object seen from one or more sides
// (docs/point_clouds.md#objects-from-a-partial-view).

#include <string>
#include <vector>

#include "hfts_db/object_database.h"
#include "preprocess/partial_view.h"

namespace hfts::preprocess {

/// Reads the segmented clouds (PCD or PLY points, metres after
/// params.scale), one per viewpoint (`view`'s own viewpoint ignored), builds
/// their object's database into DIR/<name>.h5 (`name` empty: the first
/// cloud's stem) and prints the
/// build's summary line; warnings go to standard error unless `quiet`.
/// Returns 0, or 1 when the build failed (the reason on standard error).
/// Throws std::invalid_argument (a usage error) for bad view options or a
/// number of clouds other than of viewpoints.
int viewCommand(const std::vector<std::string>& clouds,
                const std::vector<Eigen::Vector3d>& viewpoints, const std::string& name,
                const std::string& outDir, const db::BuildParameters& params, double density,
                const ViewOptions& view, bool quiet);

/// hfts-preprocess SCENE.json --depth-views: the same from the scene's
/// depth_image obstacles with a mask (robot::loadTargetViews), the masked
/// pixels the object's points and the whole images carved (carveViews).
/// `name` empty: the scene file's stem.
int depthViewCommand(const std::string& scene, const std::string& name, const std::string& outDir,
                     const db::BuildParameters& params, double density, const ViewOptions& view,
                     bool quiet);

}  // namespace hfts::preprocess
