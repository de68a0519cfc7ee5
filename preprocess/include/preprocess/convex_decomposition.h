#pragma once
// The object's solid as a set of convex pieces, for simulators that collide
// a mesh as its convex hull (MuJoCo): the hull of a mug is about four times
// its volume, the union of its pieces' hulls is close to the mug.

#include <cstdint>
#include <string>
#include <vector>

#include "hfts_db/object_database.h"
#include "hfts_db/triangle_mesh.h"

namespace hfts::preprocess {

/// How decomposeConvex splits. Defaults are those of hfts-preprocess
/// (BuildParameters::convex_parts_max and convex_parts_tolerance).
struct DecompositionOptions {
  /// At most this many pieces (1..db::kMaxConvexParts).
  std::uint32_t max_parts = 1024;
  /// Splitting ends when the pieces' volumes add up to at most 1 +
  /// tolerance times the solid's ([0, 1)). Thin curved walls need many
  /// pieces for a small tolerance: the hull of a patch of wall bulges over
  /// its concave side (docs/preprocess.md).
  double tolerance = 0.04;
  /// Voxels along the longest side of the bounding box (16..1024): cuts are
  /// chosen on them, and no cut leaves fewer than two layers of solid
  /// voxels on a side.
  std::uint32_t resolution = 128;
};

/// The pieces and what they measure.
struct ConvexDecomposition {
  std::vector<db::ConvexPiece> parts;
  double parts_volume = 0.0;  ///< sum of the pieces' volumes (m^3)
  /// Volume of the solid, where the winding number is not 0 (solidVolume);
  /// 0 for an open mesh.
  double solid_volume = 0.0;
};

/// The volume (m^3) of the solid of a closed mesh, where its winding number
/// is not 0: the divergence theorem's volume (solidProperties, exact for
/// parts that do not overlap) less what closed parts that overlap count
/// more than once, measured along vertical lines 1/256 of the longest side
/// of the bounding box apart (exact along each line, the midpoint rule
/// across them). Precondition: a mesh with triangles and finite vertices,
/// as loadMesh gives.
double solidVolume(const TriangleMesh& mesh);

/// Splits the solid of a closed mesh (where its winding number is not 0, so
/// closed parts that overlap count once) into axis-aligned boxes. Each
/// piece is the convex hull of the solid in one box: the mesh's triangles
/// clipped to the box and the box's corners in the solid. So the pieces
/// cover the solid and never overlap (the boxes do not).
///
/// Cuts are planes across x, y or z between layers of voxels (or on a flat
/// face of the mesh within a voxel and a half, so that prisms split into
/// exact boxes). First the box whose voxels are the farthest from convex is
/// split by the cut whose halves are nearest convex (voxel_convexity.h),
/// until that measure is within the tolerance overall; then the piece whose
/// hull exceeds the solid in its box by the most, by whichever of a few
/// cuts gives the smallest pieces, until the pieces' volumes add up to at
/// most 1 + tolerance times the solid's, or there are max_parts. Last,
/// neighbouring pieces whose boxes together are a box and whose hull
/// together is no larger are joined. A convex solid is one piece: its hull. An open mesh bounds no
/// solid and is one piece too, its hull. Pieces below db::minimumConvexPartVolume are left out.
/// Deterministic: the same mesh and options give the same pieces, each in the canonical order of
/// db::ConvexPiece.
///
/// Throws hfts::InvalidArgument naming the option ("max_parts",
/// "tolerance", "resolution") for a value out of range, and MeshError
/// (naming `what`) when the mesh spans no volume. Precondition: a mesh
/// with triangles and finite vertices, as loadMesh gives.
ConvexDecomposition decomposeConvex(const TriangleMesh& mesh, bool closed,
                                    const DecompositionOptions& options, const std::string& what);

}  // namespace hfts::preprocess
