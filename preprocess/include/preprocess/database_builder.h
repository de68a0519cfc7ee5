#pragma once
// The offline pipeline: mesh -> visible surface samples -> normals ->
// filtered contacts -> HFTS partition -> object database.

#include <filesystem>
#include <string>
#include <vector>

#include "hfts_db/object_database.h"
#include "hfts_db/triangle_mesh.h"
#include "preprocess/partial_view.h"

namespace hfts::preprocess {

/// Program name and version written into every database.
std::string producerName();

/// Wall time of each stage (seconds).
struct StageTimes {
  double load = 0, sample = 0, normals = 0, filter = 0, hierarchy = 0, distance_grid = 0,
         convex_parts = 0, total = 0;
};

struct BuildResult {
  db::ObjectDatabase database;
  std::vector<std::string> warnings;
  StageTimes times;
};

/// Checks parameters that do not depend on the mesh; throws
/// hfts::InvalidArgument naming the offending parameter.
void checkBuildParameters(const db::BuildParameters& params);

/// Builds the database of an in-memory mesh (already scaled to metres),
/// of the default density (db::kDefaultDensity). `closed` (the mesh's
/// topology) selects the exact volume centroid; a mesh that is not closed
/// gets centerOfMass's repair or last resort, and a warning saying which.
/// `what` names the object in errors and warnings. Throws MeshError if
/// nothing graspable remains and std::invalid_argument for bad parameters.
BuildResult buildObjectDatabase(const TriangleMesh& mesh, bool closed,
                                const db::BuildParameters& params, const std::string& what);

/// Loads `meshPath` (scaled by params.scale), builds its database and fills
/// the name, source and checksum fields. The density is the one of the
/// mesh's sidecar (readSidecar) if it has one, else `density` (kg/m^3; a
/// run's --density). Throws hfts::InvalidArgument for a bad `density`
/// ("density") or a bad sidecar (naming its file and key).
BuildResult buildObjectDatabaseFromFile(const std::filesystem::path& meshPath,
                                        const db::BuildParameters& params,
                                        double density = db::kDefaultDensity);

/// Builds the database of an object seen from one or more sides (segmented
/// point clouds in metres, in a frame whose z is up). Each view is first
/// smoothed (smoothView, unless its options' smoothing is 0); the solid is
/// what the views' hulls of their points and shadows (hiddenSide) have in
/// common; the contacts are observed points only, one per cube of
/// 1/sqrt(sample_density), with PCL's normals turned towards the camera,
/// or the sensor's normals where a view gives them; the usual filters,
/// hierarchy and grids follow. The database's partial_view records the
/// views; name and source are the caller's to fill. Throws
/// hfts::InvalidArgument ("points", "normals", "viewpoint",
/// "hidden_depth", "floor", "smoothing", prefixed "views[i]." when there
/// are several; build parameters) and MeshError when the views' solids
/// have nothing in common or no contact survives the filters.
BuildResult buildObjectDatabaseFromViews(const std::vector<SensedView>& views,
                                         const db::BuildParameters& params,
                                         const std::string& what);

/// SHA-256 of a file's bytes as lowercase hex (OpenSSL).
std::string sha256File(const std::filesystem::path& path);

}  // namespace hfts::preprocess
