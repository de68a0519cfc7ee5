#pragma once
// The object database: everything the planner needs to know about one
// object, produced offline by hfts-preprocess and stored as one HDF5 file
// (schema: docs/database.md).

#include <Eigen/Core>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "hfts_db/distance_grid.h"

namespace hfts::db {

/// Thrown when a database file cannot be read or written, or when its
/// content violates the schema. The message names the file and the problem.
class DatabaseError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Name and version of the file format written by this library.
inline constexpr const char* kObjectFormatName = "hfts-object-database";
inline constexpr std::uint32_t kObjectFormatVersion = 4;

/// Most convex parts an object database holds.
inline constexpr std::uint32_t kMaxConvexParts = 1024;

using Points3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Faces3 = Eigen::Matrix<std::uint32_t, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// Every parameter that shaped a database, stored with it so a database can
/// be rebuilt and compared. Defaults are the documented defaults of
/// hfts-preprocess (docs/preprocess.md). A database stores the filter
/// scales the build resolved (preprocess::resolveFilterScales), not 0.
struct BuildParameters {
  double scale = 1.0;                 ///< mesh units -> metres
  double sample_density = 200000.0;   ///< contacts per square metre of mesh surface
  std::uint32_t max_samples = 20000;  ///< cap on the area-uniform candidates drawn
  std::uint32_t viewpoints = 64;      ///< directions of the visibility test
  /// Radius of the fingertip pad that will touch the contacts (m); the
  /// filters' scales follow it. The default is the smallest pad of the
  /// bundled robots (the Panda gripper's; robot::padRadius).
  double pad_radius = 0.008;
  double patch_radius = 0.0;  ///< normals, curvature, neighbours (m); 0 = pad_radius / 2
  std::vector<std::string> filters = {"curvature", "concavity", "clearance", "neighbours"};
  double max_curvature = 0.03;       ///< PCL surface variation limit (scale-free)
  double max_hull_distance = 0.01;   ///< concavity limit (m)
  std::uint32_t min_neighbours = 0;  ///< within patch_radius; 0 = a third of a patch's samples
  std::vector<std::uint32_t> branching = {20, 4, 4};
  double length_scale = 0.0;             ///< k-means position scale (m); 0 = rho
  double normal_weight = 0.5;            ///< k-means weight of the unit normal
  std::uint32_t kmeans_iterations = 50;  ///< Lloyd iterations per partition
  std::uint64_t seed = 1;                ///< seeds sampling and k-means
  double distance_grid_spacing = 0.0;    ///< m; 0 = automatic (DistanceGridOptions::spacing)
  double distance_grid_margin = 0.03;    ///< m beyond the bounding box on every side
  /// Convex decomposition (preprocess::decomposeConvex): at most this many
  /// parts, 1..kMaxConvexParts.
  std::uint32_t convex_parts_max = 1024;
  /// ... splitting until the parts' volumes add up to at most 1 + this
  /// times the solid's volume, [0, 1).
  double convex_parts_tolerance = 0.04;
};

/// What the contact filters did: how many samples each removed, in order.
struct FilterReport {
  std::string name;
  std::uint64_t removed = 0;
};

/// Density of water (kg/m^3), the density of an object unless its build
/// says otherwise: most of the household objects a hand grasps weigh
/// within a factor of a few of the water they displace.
inline constexpr double kDefaultDensity = 1000.0;
/// The densities a database accepts (kg/m^3): from foams (polystyrene is
/// 15-30) to the densest metals (osmium, 22 590). Anything outside is a
/// mistake of units.
inline constexpr double kMinDensity = 10.0;
inline constexpr double kMaxDensity = 25000.0;

/// A closed convex polytope stored as its own convex hull: one piece of the
/// object's convex decomposition (object frame, metres).
struct ConvexPiece {
  Points3 vertices;  ///< corners, sorted lexicographically (x, then y, then z)
  Faces3 faces;      ///< triangles as rows of `vertices`, counter-clockwise seen from outside
};

/// The least volume (m^3) of a convex part of an object with this bounding
/// box: 1e-9 of the cube of its diagonal. Slivers below it are not stored,
/// since simulators refuse meshes of almost no volume (MuJoCo below
/// 1e-15 m^3) and they cover next to nothing.
inline double minimumConvexPartVolume(const Eigen::Vector3d& bbox_min,
                                      const Eigen::Vector3d& bbox_max) {
  const double diagonal = (bbox_max - bbox_min).norm();
  return 1e-9 * diagonal * diagonal * diagonal;
}

/// How ObjectGeometry::center_of_mass (and volume) were found, from the
/// most exact to the last resort (docs/preprocess.md#2-centre-of-mass-volume-and-rho).
enum class CenterOfMassMethod {
  kClosedMesh,    ///< "closed_mesh": the volume centroid of a closed mesh
  kRepairedMesh,  ///< "repaired_mesh": the volume centroid once the boundary of a nearly
                  ///< closed mesh (holes, dropped triangles, unwelded vertices) is capped
  kConvexHull,    ///< "convex_hull": the solid hull's centroid; the mesh bounds no volume
};

/// The name a database stores for `method` (see the enumerators).
inline std::string centerOfMassMethodName(CenterOfMassMethod method) {
  switch (method) {
    case CenterOfMassMethod::kClosedMesh:
      return "closed_mesh";
    case CenterOfMassMethod::kRepairedMesh:
      return "repaired_mesh";
    case CenterOfMassMethod::kConvexHull:
      break;
  }
  return "convex_hull";
}

/// The method a stored name means. Throws DatabaseError naming an unknown one.
inline CenterOfMassMethod parseCenterOfMassMethod(const std::string& name) {
  for (const auto method : {CenterOfMassMethod::kClosedMesh, CenterOfMassMethod::kRepairedMesh,
                            CenterOfMassMethod::kConvexHull})
    if (centerOfMassMethodName(method) == name) return method;
  throw DatabaseError("unknown center_of_mass_method '" + name +
                      "' (known: closed_mesh, repaired_mesh, convex_hull)");
}

/// Geometry of the whole object (object frame, metres).
struct ObjectGeometry {
  Eigen::Vector3d center_of_mass = Eigen::Vector3d::Zero();
  double rho = 0.0;  ///< largest distance from center_of_mass to the surface
  /// Volume of the solid (m^3): where a closed mesh's winding number is not
  /// 0 (closed parts that overlap count their overlap once); of the capped
  /// mesh when its boundary was repaired; 0 when the hull gave the centre.
  double volume = 0.0;
  bool closed = false;  ///< mesh is closed and edge-manifold (no boundary, no non-manifold edge)
  CenterOfMassMethod center_of_mass_method = CenterOfMassMethod::kConvexHull;
  Eigen::Vector3d bbox_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d bbox_max = Eigen::Vector3d::Zero();
  Points3 hull_vertices;  ///< convex hull (CGAL), vertices
  Faces3 hull_faces;      ///< convex hull triangles, outward winding
  Points3 mesh_vertices;  ///< the object's surface mesh (metres), for collision checking
  Faces3 mesh_triangles;
  /// Distances from the mesh's surface (buildDistanceGrid): signed exactly
  /// when `closed`; covers the bounding box plus the build's margin.
  DistanceGrid distance_grid;
  /// The solid as convex parts that do not overlap and whose union covers
  /// it (preprocess::decomposeConvex), for simulators that collide a mesh
  /// as its convex hull. At least one; an open mesh's single part is its
  /// hull. Their volumes add up to at least `volume`.
  std::vector<ConvexPiece> convex_parts;
};

/// One node of the Hierarchical Fingertip Space partition. Contacts are
/// stored in hierarchy order, so every node is a contiguous index range and
/// the children of a node are a contiguous range of the next level.
struct HierarchyNode {
  std::uint32_t contact_begin = 0;
  std::uint32_t contact_count = 0;
  std::uint32_t child_begin = 0;                           ///< first child in the next level
  std::uint32_t child_count = 0;                           ///< 0 exactly on the last level
  std::uint32_t representative = 0;                        ///< contact nearest to the mean position
  Eigen::Vector3d mean_normal = Eigen::Vector3d::UnitZ();  ///< normalised, outward
};

/// How a database built from partial views of the object (segmented point
/// clouds, hfts-preprocess --viewpoint) was made: its contacts are observed
/// points only, and its mesh is a conservative stand-in for what no camera
/// saw (docs/point_clouds.md#objects-from-a-partial-view). One entry per
/// view.
/// Most boxes a partial view's hidden space may hold.
inline constexpr Eigen::Index kMaxHiddenBoxes = 1'000'000;

struct PartialView {
  Points3 viewpoints;                 ///< camera centres, object frame
  std::vector<double> hidden_depths;  ///< m the unseen side may reach behind each point
  std::vector<double> floors;         ///< z (object frame) below which it does not reach
  std::vector<std::uint64_t> points;  ///< points of each view
  /// Space beside the solid that no camera saw free, so the object may
  /// reach into it: boxes (object frame, lowest and highest corners, one
  /// per row; none when the views came without their depth images). The
  /// planner keeps everything out of it, as an obstacle
  /// (robot::withHiddenSide); no contact lies in it.
  Points3 hidden_low, hidden_high;
  /// The voxel (m) the boxes are made of: their corners are multiples of
  /// it, so a cloud of this voxel holds them exactly. 0 without boxes.
  double hidden_voxel = 0.0;
};

/// A complete object database.
struct ObjectDatabase {
  std::string name;           ///< object name (the mesh file stem)
  std::string source_mesh;    ///< mesh file name the database was built from
  std::string source_sha256;  ///< SHA-256 of the mesh file bytes (hex)
  std::string producer;       ///< program and version that wrote it
  BuildParameters parameters;
  /// Density of the object's material (kg/m^3), kMinDensity..kMaxDensity:
  /// a physical property, not a build parameter. Its mass is density *
  /// geometry.volume (not stored: derived).
  double density = kDefaultDensity;
  /// Set when the database comes from a partial view, not a mesh.
  std::optional<PartialView> partial_view;
  std::uint64_t num_samples = 0;  ///< surface samples before filtering
  std::vector<FilterReport> filter_reports;
  ObjectGeometry geometry;
  Points3 positions;          ///< contact positions, hierarchy order
  Points3 normals;            ///< unit normals pointing OUT of the object
  Eigen::VectorXd curvature;  ///< PCL surface variation per contact
  /// levels[0] is the top level (branching[0] nodes at most), levels.back()
  /// the leaves. The root (all contacts) is implicit.
  std::vector<std::vector<HierarchyNode>> levels;

  std::size_t numContacts() const { return static_cast<std::size_t>(positions.rows()); }
};

/// Checks every invariant of the schema (shapes, finite values, unit
/// normals, exact partition at every level, representatives inside their
/// node, a distance grid covering the mesh, closed convex parts inside the
/// bounding box, a plausible density). Throws DatabaseError naming `what`
/// and the first violation.
void validateObjectDatabase(const ObjectDatabase& db, const std::string& what);

/// Writes `db` to `path` atomically (temporary file in the same directory,
/// then rename). Validates first; throws DatabaseError on invalid content
/// or I/O failure, leaving any existing file at `path` untouched.
void saveObjectDatabase(const ObjectDatabase& db, const std::filesystem::path& path);

/// Reads and validates a database. Throws DatabaseError for a missing,
/// truncated, corrupt (checksum), foreign, older- or newer-format file (the
/// message says how to rebuild it).
ObjectDatabase loadObjectDatabase(const std::filesystem::path& path);

}  // namespace hfts::db
