#pragma once
// The object's centre of mass and volume: exact for closed meshes, robust
// for nearly closed ones (scans), the convex hull only as a last resort.

#include <Eigen/Core>

#include <cstddef>
#include <string>

#include "hfts_db/object_database.h"
#include "hfts_db/triangle_mesh.h"
#include "preprocess/convex_hull.h"

namespace hfts::preprocess {

/// Triangles that close a mesh's boundary. The boundary is the integer
/// 1-chain of directed edges whose uses in the two directions do not cancel
/// (holes, triangles the loader dropped, unwelded vertices, flaps on a
/// non-manifold edge, triangles wound against their neighbours). Each
/// connected part of it is closed by a fan from the mean of its vertices,
/// so mesh + caps bounds a solid whatever the origin of the volume sum: a
/// dropped or flipped triangle and a flap are cancelled exactly, a planar
/// hole is filled by its plane.
struct BoundaryCaps {
  TriangleMesh caps;      ///< vertices of the mesh first, then one fan centre per part
  std::size_t parts = 0;  ///< connected parts of the boundary (0 for a closed mesh)
  double area = 0.0;      ///< total area of the caps (m^2)
  /// Sum over the parts of cap area x the largest distance of the part's
  /// vertices from their least-squares plane (m^3): how much the volume of
  /// two reasonable caps of the same holes could differ. 0 for planar holes.
  double ambiguity = 0.0;
};
BoundaryCaps boundaryCaps(const TriangleMesh& mesh);

/// The mesh with its caps (BoundaryCaps::caps, whose vertices start with
/// the mesh's): a mesh that bounds a solid.
TriangleMesh withCaps(const TriangleMesh& mesh, const TriangleMesh& caps);

/// The caps are trusted while their ambiguity is at most this fraction of
/// the capped volume: a flat hole of any size (a scan without its bottom)
/// is filled exactly, a small hole in a curved wall nearly so, but closing
/// a warped sheet would invent the solid.
inline constexpr double kMaxCapAmbiguity = 0.05;

/// The centre of mass (uniform density), the volume it was computed from
/// (0 for the hull) and which method gave it.
struct CenterOfMass {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double volume = 0.0;
  db::CenterOfMassMethod method = db::CenterOfMassMethod::kConvexHull;
  std::size_t cap_parts = 0;       ///< boundaryCaps(mesh).parts (0 for a closed mesh)
  double cap_area_fraction = 0.0;  ///< the caps' area over the mesh's
  double cap_ambiguity = 0.0;      ///< the caps' ambiguity over the capped volume
};

/// A closed mesh: its volume centroid (exact). Otherwise the volume
/// centroid of mesh + boundaryCaps(mesh), unless that volume is not
/// positive, its centroid lies outside the hull or the caps' ambiguity
/// exceeds kMaxCapAmbiguity of it: then, as a last resort, the solid hull's
/// centroid.
CenterOfMass centerOfMass(const TriangleMesh& mesh, bool closed, const ConvexHull& hull);

/// One sentence for a mesh that is not closed, naming `what` and saying
/// where its centre of mass came from (a build warning).
std::string describeCenterOfMass(const CenterOfMass& com, const std::string& what);

}  // namespace hfts::preprocess
