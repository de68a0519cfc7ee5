#pragma once
// Embree's BVH over a triangle mesh: ray occlusion and nearest-surface
// queries. Embree itself stays inside triangle_bvh.cpp.

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <optional>

#include "hfts_db/triangle_mesh.h"

namespace hfts::db {

/// The point of a mesh nearest to a query point.
struct ClosestPoint {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double distance = 0.0;       ///< |query - point|, computed in double
  std::uint32_t triangle = 0;  ///< a triangle that contains `point`
};

/// Where a ray first meets a mesh.
struct RayHit {
  double distance = 0.0;  ///< along the ray, in units of its direction's length
  std::uint32_t triangle = 0;
};

class TriangleBvh {
 public:
  /// Builds the BVH (one thread). Keeps a copy of the mesh for distance
  /// queries. Throws std::runtime_error if Embree fails.
  explicit TriangleBvh(const TriangleMesh& mesh);
  ~TriangleBvh();
  TriangleBvh(const TriangleBvh&) = delete;
  TriangleBvh& operator=(const TriangleBvh&) = delete;

  /// True when a ray from `origin` along `direction` hits no triangle.
  bool escapes(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const;

  /// The first triangle a ray from `origin` along `direction` meets
  /// (Embree's single-precision intersection), or nullopt.
  std::optional<RayHit> firstHit(const Eigen::Vector3d& origin,
                                 const Eigen::Vector3d& direction) const;

  /// True when some triangle comes within `radius` of `point`.
  bool isWithin(const Eigen::Vector3d& point, double radius) const;

  /// The exact nearest point of the mesh: the smallest double-precision
  /// point-triangle distance over all triangles (Embree's single-precision
  /// BVH only culls, with a margin for its rounding). `hint` is a triangle
  /// tried first; the answer of a nearby query makes the search faster.
  /// A mesh without triangles gives an infinite distance.
  ClosestPoint closestPoint(const Eigen::Vector3d& point, std::uint32_t hint = 0) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The point of triangle (a, b, c) closest to p.
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c);

}  // namespace hfts::db
