#pragma once
// Triangle meshes and their import (assimp), shared by the offline stage
// (sampling objects) and the planner (mesh obstacles).

#include <Eigen/Core>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "hfts_db/isolation_limits.h"

namespace hfts {

/// Thrown for a mesh that cannot be used: unreadable, empty, degenerate or
/// non-finite. The message names the file and the problem.
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

using Vertices = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Triangles = Eigen::Matrix<std::uint32_t, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// An indexed triangle mesh in metres.
struct TriangleMesh {
  Vertices vertices;
  Triangles triangles;
};

/// Edge structure of a mesh: whether it bounds a volume.
struct MeshTopology {
  std::size_t boundary_edges = 0;      ///< edges used by one triangle
  std::size_t non_manifold_edges = 0;  ///< edges used by three or more triangles
  std::size_t inconsistent_edges = 0;  ///< edges both triangles traverse the same way
  bool closed() const {
    return boundary_edges == 0 && non_manifold_edges == 0 && inconsistent_edges == 0;
  }
};

/// Result of loading: the mesh plus what the loader noticed.
struct LoadedMesh {
  TriangleMesh mesh;
  MeshTopology topology;
  std::size_t dropped_degenerate = 0;  ///< zero-area triangles removed
  std::vector<std::string> warnings;   ///< e.g. open or non-manifold mesh
};

/// Loads STL (binary and ASCII), PLY, OBJ, DAE and the other formats of
/// assimp, flattening the scene graph, merging identical vertices,
/// multiplying coordinates by `scale` (e.g. 0.001 for millimetres) and
/// dropping zero-area triangles. Throws MeshError when the file cannot be
/// read or holds no usable surface (no triangles, all degenerate, non-finite
/// coordinates, or all vertices in one plane). Open or non-manifold meshes
/// load with a warning.
///
/// assimp runs in a child process (runIsolated) within `limits`: some
/// malformed files make it crash or loop, which then gives a MeshError
/// naming the file. Without `limits`, meshImportLimits(file size).
LoadedMesh loadMesh(const std::filesystem::path& path, double scale = 1.0,
                    const std::optional<IsolationLimits>& limits = std::nullopt);

/// The default limits of an import: 60 s plus 1 s per MiB of file, 2 GiB
/// of memory plus 64 bytes per byte of file.
IsolationLimits meshImportLimits(std::uintmax_t fileBytes);

/// Checks an in-memory mesh the same way (used by loadMesh); `what` names
/// it in errors. Removes zero-area triangles and returns their count.
std::size_t sanitizeMesh(TriangleMesh& mesh, const std::string& what);

/// Counts boundary, non-manifold and inconsistently wound edges.
MeshTopology analyzeTopology(const TriangleMesh& mesh);

/// Total surface area (m^2).
double surfaceArea(const TriangleMesh& mesh);

/// Volume and centroid of the solid bounded by a closed mesh (divergence
/// theorem over signed tetrahedra). The volume is returned positive. Closed
/// parts that overlap count their overlap once per part.
struct SolidProperties {
  double volume = 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
};
SolidProperties solidProperties(const TriangleMesh& mesh);

/// A closed box of the given size centred at the origin, its triangles
/// turned outwards (12 triangles on 8 corners).
TriangleMesh boxMesh(const Eigen::Vector3d& size);

}  // namespace hfts
