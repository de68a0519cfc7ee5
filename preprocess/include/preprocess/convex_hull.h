#pragma once
// The object's convex hull (CGAL) and the geometry derived from it.

#include <Eigen/Core>

#include <memory>
#include <vector>

#include "hfts_db/object_database.h"
#include "hfts_db/triangle_bvh.h"
#include "hfts_db/triangle_mesh.h"

namespace hfts::preprocess {

/// CGAL's 3-D hull of the points in canonical order: vertices sorted
/// lexicographically, only the corners of the facets kept, every polygonal
/// facet a fan from its smallest corner, the triangles sorted. So it is a
/// function of the points alone, whatever their order. Throws MeshError
/// (naming `what`) if the points do not span a volume.
db::ConvexPiece canonicalHull(const Vertices& points, const std::string& what);

/// A convex polytope as triangles plus one outward plane per triangle.
class ConvexHull {
 public:
  /// CGAL's 3-D hull of the points. Throws MeshError (naming `what`) if the
  /// points do not span a volume.
  ConvexHull(const Vertices& points, const std::string& what);

  const db::Points3& vertices() const { return vertices_; }
  const db::Faces3& faces() const { return faces_; }
  ConvexHull(ConvexHull&&) noexcept;
  ~ConvexHull();
  /// Distance from a point inside (or on) the hull to the hull's boundary;
  /// negative outside. Linear in the number of hull faces.
  double depth(const Eigen::Vector3d& p) const;
  /// Whether depth(p) <= limit for a point inside or on the hull (such as
  /// a surface contact), answered through a BVH of the hull triangles in
  /// logarithmic time (the concavity filter's query). Precondition: p is
  /// not farther than `limit` outside the hull.
  bool isShallow(const Eigen::Vector3d& p, double limit) const;
  /// One outward plane per face (n.x, n.y, n.z, d: n.p + d <= 0 inside);
  /// a sliver's row is (0, 0, 0, -infinity), never the nearest.
  const Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>& planes() const {
    return planes_;
  }
  /// Centroid of the solid hull.
  Eigen::Vector3d centroid() const;

 private:
  db::Points3 vertices_;
  db::Faces3 faces_;
  Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> planes_;  // n.x, n.y, n.z, d
  std::unique_ptr<db::TriangleBvh> bvh_;
};

}  // namespace hfts::preprocess
