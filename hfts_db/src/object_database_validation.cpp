// The schema's invariants, checked before every save and after every load.
#include <Eigen/Geometry>
#include <algorithm>

#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <utility>

#include "hfts_db/object_database.h"
#include "hfts_db/triangle_mesh.h"

namespace hfts::db {
namespace {

constexpr double kUnitTolerance = 1e-6;

class Checker {
 public:
  explicit Checker(const std::string& what) : what_(what) {}

  void require(bool condition, const std::string& problem) const {
    if (!condition) throw DatabaseError(what_ + ": " + problem);
  }

  template <typename Derived>
  void requireFinite(const Eigen::MatrixBase<Derived>& m, const std::string& name) const {
    require(m.allFinite(), name + " holds non-finite values");
  }

  void requireUnitRows(const Points3& m, const std::string& name) const {
    for (Eigen::Index i = 0; i < m.rows(); ++i)
      require(std::abs(m.row(i).norm() - 1.0) < kUnitTolerance,
              name + " row " + std::to_string(i) + " is not a unit vector");
  }

 private:
  std::string what_;
};

double signedVolume(const ConvexPiece& part) {
  double six = 0.0;
  const Eigen::RowVector3d o = part.vertices.row(0);
  for (Eigen::Index t = 0; t < part.faces.rows(); ++t) {
    const Eigen::Vector3d a = (part.vertices.row(part.faces(t, 0)) - o).transpose();
    const Eigen::Vector3d b = (part.vertices.row(part.faces(t, 1)) - o).transpose();
    const Eigen::Vector3d d = (part.vertices.row(part.faces(t, 2)) - o).transpose();
    six += a.dot(b.cross(d));
  }
  return six / 6.0;
}

/// Whether no corner of a face's neighbour lies more than `tolerance` in
/// front of the face (for faces of some area), and the face angles around
/// every vertex add up to at most 2 pi.
bool convexEdges(const ConvexPiece& part, double tolerance) {
  const auto corner = [&](std::uint32_t v) -> Eigen::Vector3d {
    return part.vertices.row(v).transpose();
  };
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> opposite;  // edge -> corner
  std::vector<double> angles(static_cast<std::size_t>(part.vertices.rows()), 0.0);
  for (Eigen::Index t = 0; t < part.faces.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = part.faces(t, k), b = part.faces(t, (k + 1) % 3),
                          d = part.faces(t, (k + 2) % 3);
      opposite[{a, b}] = d;
      const Eigen::Vector3d u = corner(b) - corner(a), w = corner(d) - corner(a);
      angles[a] += std::atan2(u.cross(w).norm(), u.dot(w));
    }
  for (double angle : angles)
    if (angle > 2.0 * M_PI + 1e-6) return false;
  for (const auto& [edge, d] : opposite) {
    const auto other = opposite.find({edge.second, edge.first});
    if (other == opposite.end()) return false;
    const Eigen::Vector3d a = corner(edge.first);
    const Eigen::Vector3d n = (corner(edge.second) - a).cross(corner(d) - a);
    const double area2 = n.norm();
    if (area2 > tolerance * (corner(edge.second) - a).norm() &&
        n.dot(corner(other->second) - a) > tolerance * area2)
      return false;
  }
  return true;
}

void checkGeometry(const Checker& c, const ObjectGeometry& g) {
  c.requireFinite(g.center_of_mass, "center_of_mass");
  c.require(std::isfinite(g.rho) && g.rho > 0.0, "rho must be positive");
  c.require(std::isfinite(g.volume) && g.volume >= 0.0, "volume must be >= 0");
  c.requireFinite(g.bbox_min, "bbox_min");
  c.requireFinite(g.bbox_max, "bbox_max");
  c.require((g.bbox_min.array() <= g.bbox_max.array()).all(), "bbox_min exceeds bbox_max");
  c.require(g.hull_vertices.rows() >= 4, "the convex hull needs at least 4 vertices");
  c.require(g.hull_faces.rows() >= 4, "the convex hull needs at least 4 faces");
  c.requireFinite(g.hull_vertices, "hull_vertices");
  c.require(g.hull_faces.maxCoeff() < static_cast<std::uint32_t>(g.hull_vertices.rows()),
            "hull_faces index a vertex that does not exist");
  c.require(g.mesh_vertices.rows() >= 4 && g.mesh_triangles.rows() >= 4,
            "the object mesh needs at least 4 vertices and 4 triangles");
  c.requireFinite(g.mesh_vertices, "mesh_vertices");
  c.require(g.mesh_triangles.maxCoeff() < static_cast<std::uint32_t>(g.mesh_vertices.rows()),
            "mesh_triangles index a vertex that does not exist");
}

void checkDistanceGrid(const Checker& c, const ObjectGeometry& g) {
  const DistanceGrid& grid = g.distance_grid;
  c.require(grid.dims[0] >= 2 && grid.dims[1] >= 2 && grid.dims[2] >= 2,
            "distance_grid.dims must be at least 2 along each axis");
  c.require(std::isfinite(grid.spacing) && grid.spacing > 0.0,
            "distance_grid.spacing must be positive and finite");
  c.requireFinite(grid.origin, "distance_grid.origin");
  const std::uint64_t nodes = std::uint64_t{grid.dims[0]} * grid.dims[1] * grid.dims[2];
  c.require(nodes <= kMaxGridNodes,
            "distance_grid.dims give more than " + std::to_string(kMaxGridNodes) + " nodes");
  c.require(grid.values.size() == nodes, "distance_grid.values holds " +
                                             std::to_string(grid.values.size()) +
                                             " values, dims need " + std::to_string(nodes));
  c.require(
      std::all_of(grid.values.begin(), grid.values.end(), [](float v) { return std::isfinite(v); }),
      "distance_grid.values holds non-finite values");
  c.require(grid.boundary_min <= boundaryMinimum(grid),
            "distance_grid.boundary_min exceeds the smallest value on the grid's faces");
  c.require((grid.origin.array() <= g.bbox_min.array()).all() &&
                (grid.boxMax().array() >= g.bbox_max.array()).all(),
            "distance_grid does not cover the bounding box");
  c.require(grid.is_signed == g.closed, "distance_grid.signed must equal closed");
}

/// The space no camera saw free: boxes.
void checkHidden(const Checker& c, const PartialView& v) {
  c.require(v.hidden_low.rows() == v.hidden_high.rows(),
            "partial_view.hidden_low and hidden_high differ in their number of boxes");
  c.requireFinite(v.hidden_low, "partial_view.hidden_low");
  c.requireFinite(v.hidden_high, "partial_view.hidden_high");
  c.require((v.hidden_low.array() < v.hidden_high.array()).all(),
            "partial_view: every hidden box needs hidden_low < hidden_high");
  c.require(v.hidden_low.rows() == 0 || (std::isfinite(v.hidden_voxel) && v.hidden_voxel > 0.0),
            "partial_view.hidden_voxel must be positive when there are hidden boxes");
  c.require(v.hidden_low.rows() <= kMaxHiddenBoxes,
            "partial_view holds more than " + std::to_string(kMaxHiddenBoxes) + " hidden boxes");
}

/// Closed, outward, convex within `tolerance` (m), at least `minVolume`.
/// Convex is checked locally (Hadamard): a closed surface of genus 0 whose
/// every edge bends outward (the far corner of each neighbour is not in
/// front of a face) and whose face angles around every vertex add up to at
/// most 2 pi bounds a convex body. That takes time linear in the faces,
/// where testing every vertex against every face would not.
void checkConvexPart(const Checker& c, const ConvexPiece& part, const std::string& name,
                     double tolerance, double minVolume) {
  const TriangleMesh mesh{part.vertices, part.faces};
  c.require(part.vertices.rows() >= 4 && part.faces.rows() >= 4,
            name + " needs at least 4 vertices and 4 faces");
  c.requireFinite(part.vertices, name + " vertices");
  c.require(part.faces.maxCoeff() < static_cast<std::uint32_t>(part.vertices.rows()),
            name + " faces index a vertex that does not exist");
  c.require(analyzeTopology(mesh).closed(), name + " is not a closed, consistently wound surface");
  c.require(part.vertices.rows() - part.faces.rows() / 2 == 2,
            name + " is not one surface of genus 0");
  const double volume = signedVolume(part);
  c.require(volume > 0.0, name + " is wound inward");
  c.require(convexEdges(part, tolerance), name + " is not convex");
  c.require(volume >= minVolume, name + " holds less than the least volume of a part (" +
                                     std::to_string(minVolume) + " m^3)");
}

void checkConvexParts(const Checker& c, const ObjectGeometry& g) {
  c.require(!g.convex_parts.empty() && g.convex_parts.size() <= kMaxConvexParts,
            "convex_parts must hold 1 to " + std::to_string(kMaxConvexParts) + " parts");
  const double diagonal = (g.bbox_max - g.bbox_min).norm();
  const double slack = 1e-6 * diagonal + 1e-9;
  for (std::size_t i = 0; i < g.convex_parts.size(); ++i) {
    const ConvexPiece& part = g.convex_parts[i];
    const std::string name = "convex part " + std::to_string(i);
    checkConvexPart(c, part, name, 1e-9 * diagonal,
                    minimumConvexPartVolume(g.bbox_min, g.bbox_max));
    const Eigen::Array3d lo = part.vertices.colwise().minCoeff().transpose();
    const Eigen::Array3d hi = part.vertices.colwise().maxCoeff().transpose();
    c.require((lo >= g.bbox_min.array() - slack).all() && (hi <= g.bbox_max.array() + slack).all(),
              name + " reaches outside the bounding box");
  }
}

void checkContacts(const Checker& c, const ObjectDatabase& db) {
  const Eigen::Index n = db.positions.rows();
  c.require(n > 0, "the database holds no contacts");
  c.require(db.normals.rows() == n && db.curvature.size() == n,
            "positions, normals and curvature differ in length");
  c.requireFinite(db.positions, "positions");
  c.requireFinite(db.normals, "normals");
  c.requireFinite(db.curvature, "curvature");
  c.requireUnitRows(db.normals, "normals");
  const ObjectGeometry& g = db.geometry;
  const double slack = 1e-6 * (g.bbox_max - g.bbox_min).norm() + 1e-9;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d p = db.positions.row(i).transpose();
    c.require((p.array() >= g.bbox_min.array() - slack).all() &&
                  (p.array() <= g.bbox_max.array() + slack).all(),
              "contact " + std::to_string(i) + " lies outside the bounding box");
  }
}

/// The representative must be (one of) the contacts nearest to the mean
/// position of its node.
void checkRepresentative(const Checker& c, const ObjectDatabase& db, const HierarchyNode& node,
                         const std::string& name) {
  const Eigen::Index begin = node.contact_begin;
  const Eigen::Index count = node.contact_count;
  c.require(node.representative >= node.contact_begin &&
                node.representative - node.contact_begin < node.contact_count,
            name + ": representative lies outside the node");
  const Eigen::RowVector3d mean = db.positions.middleRows(begin, count).colwise().mean();
  const double best =
      (db.positions.middleRows(begin, count).rowwise() - mean).rowwise().squaredNorm().minCoeff();
  const double chosen = (db.positions.row(node.representative) - mean).squaredNorm();
  c.require(chosen <= best + 1e-12 * (1.0 + best),
            name + ": representative is not the contact nearest to the mean");
  c.require(std::abs(node.mean_normal.norm() - 1.0) < kUnitTolerance,
            name + ": mean_normal is not a unit vector");
}

/// Nodes of `level` must cover [begin, end) contiguously, in order.
void checkLevel(const Checker& c, const ObjectDatabase& db, std::size_t level) {
  const std::vector<HierarchyNode>& nodes = db.levels[level];
  const bool last = level + 1 == db.levels.size();
  const std::size_t nextSize = last ? 0 : db.levels[level + 1].size();
  std::uint64_t expectedChild = 0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const HierarchyNode& node = nodes[i];
    const std::string name = "level " + std::to_string(level + 1) + " node " + std::to_string(i);
    c.require(node.contact_count > 0, name + " is empty");
    c.require(std::uint64_t{node.contact_begin} + node.contact_count <= db.numContacts(),
              name + " exceeds the contacts");
    checkRepresentative(c, db, node, name);
    if (last) {
      c.require(node.child_count == 0, name + " is a leaf but has children");
      continue;
    }
    c.require(node.child_count >= 1 && node.child_count <= db.parameters.branching[level + 1],
              name + " has " + std::to_string(node.child_count) + " children");
    c.require(node.child_begin == expectedChild, name + ": children are not contiguous");
    expectedChild += node.child_count;
    c.require(expectedChild <= nextSize, name + ": children exceed the next level");
    std::uint64_t cursor = node.contact_begin;
    for (std::uint32_t k = node.child_begin; k < node.child_begin + node.child_count; ++k) {
      const HierarchyNode& child = db.levels[level + 1][k];
      c.require(child.contact_begin == cursor, name + ": children do not partition it");
      cursor += child.contact_count;
    }
    c.require(cursor == std::uint64_t{node.contact_begin} + node.contact_count,
              name + ": children do not partition it");
  }
  if (!last)
    c.require(expectedChild == nextSize,
              "level " + std::to_string(level + 2) + " holds nodes without a parent");
}

void checkHierarchy(const Checker& c, const ObjectDatabase& db) {
  const std::vector<std::uint32_t>& branching = db.parameters.branching;
  c.require(!branching.empty(), "branching is empty");
  for (std::uint32_t b : branching) c.require(b >= 1, "branching factors must be >= 1");
  c.require(db.levels.size() == branching.size(), "number of levels differs from branching");
  const std::vector<HierarchyNode>& top = db.levels.front();
  c.require(!top.empty() && top.size() <= branching.front(), "top level has a wrong size");
  std::uint64_t cursor = 0;
  for (const HierarchyNode& node : top) {
    c.require(node.contact_begin == cursor, "top level does not partition the contacts");
    cursor += node.contact_count;
  }
  c.require(cursor == db.numContacts(), "top level does not partition the contacts");
  for (std::size_t level = 0; level < db.levels.size(); ++level) checkLevel(c, db, level);
}

}  // namespace

void validateObjectDatabase(const ObjectDatabase& db, const std::string& what) {
  const Checker c(what);
  c.require(std::isfinite(db.density) && db.density >= kMinDensity && db.density <= kMaxDensity,
            "density must be in [" + std::to_string(kMinDensity) + ", " +
                std::to_string(kMaxDensity) + "] kg/m^3, got " + std::to_string(db.density));
  if (db.partial_view) {
    const PartialView& v = *db.partial_view;
    const auto views = static_cast<std::size_t>(v.viewpoints.rows());
    c.require(views > 0 && v.hidden_depths.size() == views && v.floors.size() == views &&
                  v.points.size() == views,
              "partial_view needs one viewpoint, hidden depth, floor and point count per view");
    c.require(v.viewpoints.allFinite(), "partial_view.viewpoints must be finite");
    for (std::size_t i = 0; i < v.hidden_depths.size(); ++i) {
      c.require(std::isfinite(v.hidden_depths[i]) && v.hidden_depths[i] > 0.0,
                "partial_view.hidden_depths must be positive");
      c.require(std::isfinite(v.floors[i]), "partial_view.floors must be finite");
      c.require(v.points[i] > 0, "partial_view.points must be positive");
    }
    checkHidden(c, v);
  }
  checkGeometry(c, db.geometry);
  checkDistanceGrid(c, db.geometry);
  checkConvexParts(c, db.geometry);
  checkContacts(c, db);
  checkHierarchy(c, db);
}

}  // namespace hfts::db
