// The schema's invariants, checked before every save and after every load.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "hfts_db/object_database.h"

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
  checkGeometry(c, db.geometry);
  checkDistanceGrid(c, db.geometry);
  checkContacts(c, db);
  checkHierarchy(c, db);
}

}  // namespace hfts::db
