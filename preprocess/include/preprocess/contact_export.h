#pragma once

#include <array>
#include <filesystem>

#include "hfts_db/object_database.h"

namespace hfts::preprocess {

/// Writes the contacts as an ASCII PLY point cloud with normals, coloured by
/// top-level cluster, so the partition can be looked at in any point cloud
/// viewer. Atomic; throws std::runtime_error if the file cannot be written.
void exportContactsPly(const db::ObjectDatabase& db, const std::filesystem::path& path);

/// The colour (r, g, b) of cluster `index`: distinct for neighbouring indices.
std::array<unsigned char, 3> clusterColour(std::size_t index);

}  // namespace hfts::preprocess
