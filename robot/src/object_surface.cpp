#include "robot/object_surface.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <string>

#include "core/invalid_argument.h"

namespace hfts::robot {

namespace {

std::uint64_t edgeKey(std::uint32_t a, std::uint32_t b) {
  return (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
}

/// A box cell of a shape's bounding box (shape frame) and what is known of
/// the signed distance over the part of the shape inside it.
struct Cell {
  Eigen::Vector3d center;
  Eigen::Vector3d half;
  double bound = 0.0;  ///< no point of the shape in the cell has a smaller signed distance
  double reach = 0.0;  ///< farthest point of the cell from the point evaluated for it
  bool exact = false;  ///< `bound` comes from an exact query, not only the grid
};

struct ByBound {
  bool operator()(const Cell& a, const Cell& b) const { return a.bound > b.bound; }
};

/// The point of the shape (its frame: centred, a cylinder along z) nearest
/// to x: the shapes are convex, so it is unique.
Eigen::Vector3d clampInto(const CollisionShape& shape, const Eigen::Vector3d& x) {
  switch (shape.type) {
    case CollisionShape::Type::kBox: {
      const Eigen::Vector3d half = shape.size / 2;
      return x.cwiseMax(-half).cwiseMin(half);
    }
    case CollisionShape::Type::kCylinder: {
      const double r = shape.size.x(), h = shape.size.y() / 2;
      Eigen::Vector3d out(x.x(), x.y(), std::clamp(x.z(), -h, h));
      const double radial = std::hypot(x.x(), x.y());
      if (radial > r) out.head<2>() *= r / radial;
      return out;
    }
    case CollisionShape::Type::kSphere:
    default: {
      const double r = shape.size.x(), n = x.norm();
      return n > r ? Eigen::Vector3d(x * (r / n)) : x;
    }
  }
}

/// Evaluations after which shapeDistance returns its current lower bound
/// (still a valid bound, only not within the tolerance). A fingertip on a
/// face needs a few hundred.
constexpr int kMaxEvaluations = 20000;

}  // namespace

struct ObjectSurface::Fcl {
  std::unique_ptr<fcl::CollisionObjectd> mesh;  // object frame; queries only read it
};

ObjectSurface::ObjectSurface(const db::ObjectGeometry& geometry)
    : vertices_(geometry.mesh_vertices),
      triangles_(geometry.mesh_triangles),
      grid_(geometry.distance_grid) {
  if (triangles_.rows() == 0 || !vertices_.allFinite())
    throw InvalidArgument("geometry", "needs a mesh with triangles and finite vertices");
  if (triangles_.maxCoeff() >= static_cast<std::uint32_t>(vertices_.rows()))
    throw InvalidArgument("geometry", "a triangle names a vertex that does not exist");
  bvh_ = std::make_unique<db::TriangleBvh>(TriangleMesh{vertices_, triangles_});
  const auto vertex = [&](std::uint32_t v) -> Eigen::Vector3d {
    return vertices_.row(v).transpose();
  };
  vertexNormals_.assign(static_cast<std::size_t>(vertices_.rows()), Eigen::Vector3d::Zero());
  for (Eigen::Index t = 0; t < triangles_.rows(); ++t) {
    const std::uint32_t v[3] = {triangles_(t, 0), triangles_(t, 1), triangles_(t, 2)};
    const Eigen::Vector3d n =
        (vertex(v[1]) - vertex(v[0])).cross(vertex(v[2]) - vertex(v[0])).normalized();
    faceNormals_.push_back(n.allFinite() ? n : Eigen::Vector3d::Zero());
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e1 = vertex(v[(k + 1) % 3]) - vertex(v[k]);
      const Eigen::Vector3d e2 = vertex(v[(k + 2) % 3]) - vertex(v[k]);
      const double angle = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
      vertexNormals_[v[k]] += angle * faceNormals_.back();
      // operator[] would leave a new Eigen vector uninitialised.
      edgeNormals_.try_emplace(edgeKey(v[k], v[(k + 1) % 3]), Eigen::Vector3d::Zero())
          .first->second += faceNormals_.back();
    }
  }
  for (Eigen::Vector3d& n : vertexNormals_)
    if (n.norm() > 0.0) n.normalize();
  for (auto& [key, n] : edgeNormals_)
    if (n.norm() > 0.0) n.normalize();
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Vector3d> points;
  std::vector<fcl::Triangle> faces;
  for (Eigen::Index v = 0; v < vertices_.rows(); ++v) points.emplace_back(vertices_.row(v));
  for (Eigen::Index t = 0; t < triangles_.rows(); ++t)
    faces.emplace_back(triangles_(t, 0), triangles_(t, 1), triangles_(t, 2));
  model->beginModel();
  model->addSubModel(points, faces);
  model->endModel();
  auto fcl = std::make_unique<Fcl>();
  fcl->mesh = std::make_unique<fcl::CollisionObjectd>(model);
  fcl->mesh->computeAABB();
  fcl_ = std::move(fcl);
}

ObjectSurface::~ObjectSurface() = default;

double ObjectSurface::gridBound(const Eigen::Vector3d& p) const {
  // An unsigned grid bounds |sd| only: a point may be inside the solid.
  if (grid_.empty() || !grid_.is_signed) return -std::numeric_limits<double>::infinity();
  return grid_.lowerBound(p);
}

Eigen::Vector3d ObjectSurface::pseudoNormal(std::uint32_t triangle,
                                            const Eigen::Vector3d& point) const {
  const std::uint32_t v[3] = {triangles_(triangle, 0), triangles_(triangle, 1),
                              triangles_(triangle, 2)};
  const Eigen::Vector3d a = vertices_.row(v[0]), b = vertices_.row(v[1]), c = vertices_.row(v[2]);
  const Eigen::Vector3d e0 = b - a, e1 = c - a, p = point - a;
  const double d00 = e0.dot(e0), d01 = e0.dot(e1), d11 = e1.dot(e1);
  const double d20 = p.dot(e0), d21 = p.dot(e1), denominator = d00 * d11 - d01 * d01;
  if (!(denominator > 0.0)) return faceNormals_[triangle];
  const double wb = (d11 * d20 - d01 * d21) / denominator;
  const double wc = (d00 * d21 - d01 * d20) / denominator;
  const double weights[3] = {1.0 - wb - wc, wb, wc};
  // Which feature holds the point: a barycentric weight of (almost) 0
  // puts it on the opposite edge, two of them on a vertex.
  constexpr double kOnFeature = 1e-9;
  int zeros = 0, lastNonZero = 0, zero = 0;
  for (int k = 0; k < 3; ++k) {
    if (weights[k] <= kOnFeature) {
      ++zeros;
      zero = k;
    } else {
      lastNonZero = k;
    }
  }
  if (zeros == 0) return faceNormals_[triangle];
  if (zeros >= 2) return vertexNormals_[v[lastNonZero]];
  return edgeNormals_.at(edgeKey(v[(zero + 1) % 3], v[(zero + 2) % 3]));
}

SurfacePoint ObjectSurface::nearest(const Eigen::Vector3d& p) const {
  const db::ClosestPoint closest = bvh_->closestPoint(p);
  SurfacePoint out;
  out.point = closest.point;
  out.normal = pseudoNormal(closest.triangle, closest.point);
  out.signed_distance =
      (p - closest.point).dot(out.normal) < 0.0 ? -closest.distance : closest.distance;
  return out;
}

ShapeDistance ObjectSurface::shapeDistance(const CollisionShape& shape,
                                           const Eigen::Isometry3d& pose, double tolerance,
                                           double stopAbove, double stopBelow) const {
  if (!(tolerance > 0.0)) throw InvalidArgument("tolerance", "must be > 0");
  ShapeDistance best;
  best.shape_point = pose.translation();
  double found = std::numeric_limits<double>::infinity();  // smallest exact value
  std::priority_queue<Cell, std::vector<Cell>, ByBound> open;
  int evaluations = 0;
  // A cell is pushed with the grid's bound (cheap); only when it comes to
  // the top is its point evaluated exactly, and only then is it split.
  const auto push = [&](const Eigen::Vector3d& center, const Eigen::Vector3d& half) {
    const Eigen::Vector3d inside = clampInto(shape, center);
    if ((center - inside).norm() > half.norm()) return;  // the cell misses the shape
    const double reach = (center - inside).norm() + half.norm();
    open.push({center, half, gridBound(pose * inside) - reach, reach, false});
  };
  const auto evaluate = [&](Cell cell) {
    const Eigen::Vector3d at = pose * clampInto(shape, cell.center);
    const SurfacePoint s = nearest(at);
    ++evaluations;
    if (s.signed_distance < found) {
      found = s.signed_distance;
      best.shape_point = at;
      best.surface = s;
    }
    cell.bound = std::max(cell.bound, s.signed_distance - cell.reach);
    cell.exact = true;
    open.push(cell);
  };
  // Roughly cubic cells to start with: a long cylinder is a row of them.
  const Eigen::Vector3d extent = halfExtents(shape);
  const double side = extent.minCoeff();
  Eigen::Vector3i count;
  for (int k = 0; k < 3; ++k)
    count[k] = std::max(1, static_cast<int>(std::ceil(extent[k] / side - 1e-9)));
  const Eigen::Vector3d half = extent.cwiseQuotient(count.cast<double>());
  for (int i = 0; i < count.x(); ++i)
    for (int j = 0; j < count.y(); ++j)
      for (int k = 0; k < count.z(); ++k)
        push(-extent + half.cwiseProduct(Eigen::Vector3d(2 * i + 1, 2 * j + 1, 2 * k + 1)), half);
  while (!open.empty()) {
    const Cell cell = open.top();
    if (cell.bound >= found - tolerance || cell.bound > stopAbove || found < stopBelow ||
        evaluations >= kMaxEvaluations)
      break;
    open.pop();
    if (!cell.exact) {
      evaluate(cell);
      continue;
    }
    Eigen::Index axis = 0;
    cell.half.maxCoeff(&axis);
    Eigen::Vector3d childHalf = cell.half;
    childHalf[axis] /= 2;
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();
    offset[axis] = childHalf[axis];
    push(cell.center - offset, childHalf);
    push(cell.center + offset, childHalf);
  }
  best.lower = std::min(found, open.empty() ? found : open.top().bound);
  return best;
}

Clearance ObjectSurface::linkClearance(const Link& link, const Eigen::Isometry3d& linkPose) const {
  Clearance best;
  best.distance = std::numeric_limits<double>::infinity();
  for (const CollisionShape& shape : link.shapes) {
    std::shared_ptr<fcl::CollisionGeometryd> geometry;
    if (shape.type == CollisionShape::Type::kBox)
      geometry = std::make_shared<fcl::Boxd>(shape.size.x(), shape.size.y(), shape.size.z());
    else if (shape.type == CollisionShape::Type::kCylinder)
      geometry = std::make_shared<fcl::Cylinderd>(shape.size.x(), shape.size.y());
    else
      geometry = std::make_shared<fcl::Sphered>(shape.size.x());
    const Eigen::Isometry3d pose = linkPose * shape.origin;
    const fcl::CollisionObjectd object(geometry, pose.linear(), pose.translation());
    fcl::DistanceRequestd request(true, false, 0.0, 0.0, 1e-6, fcl::GST_INDEP);
    fcl::DistanceResultd result;
    // The mesh first: FCL 0.7 gives the mesh's nearest point first then, in
    // the mesh's frame (the object frame); the shape's it gives in the
    // shape's own frame, so it is found here instead, as the shape's point
    // nearest to the mesh's (the shapes are convex).
    fcl::distance(fcl_->mesh.get(), &object, request, result);
    // In touch FCL answers 0, a negative number or a denormal.
    constexpr double kTouching = 1e-9;
    const double d = result.min_distance > kTouching ? result.min_distance : 0.0;
    if (d < best.distance) {
      best.distance = d;
      best.on_surface = result.nearest_points[0];
      best.on_link = pose * clampInto(shape, pose.inverse() * best.on_surface);
    }
  }
  return best;
}

double ObjectSurface::linkDepth(const Link& link, const Eigen::Isometry3d& linkPose,
                                double tolerance) const {
  if (link.shapes.empty()) return 0.0;
  // Apart from the triangles, the link is wholly outside or wholly inside.
  const Eigen::Vector3d somePoint = linkPose * link.shapes.front().origin.translation();
  if (linkClearance(link, linkPose).distance > 0.0 && nearest(somePoint).signed_distance > 0.0)
    return 0.0;
  return std::max(0.0, -linkDistance(link, linkPose, tolerance).lower);
}

ShapeDistance ObjectSurface::linkDistance(const Link& link, const Eigen::Isometry3d& linkPose,
                                          double tolerance, double stopAbove,
                                          double stopBelow) const {
  ShapeDistance best;
  best.lower = std::numeric_limits<double>::infinity();
  for (const CollisionShape& shape : link.shapes) {
    const ShapeDistance d =
        shapeDistance(shape, linkPose * shape.origin, tolerance, stopAbove, stopBelow);
    if (d.lower < best.lower) best = d;
  }
  return best;
}

}  // namespace hfts::robot
