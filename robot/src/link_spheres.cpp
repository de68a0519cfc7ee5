#include "robot/link_spheres.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

namespace hfts::robot {
namespace {

/// A box of the shape's volume grid: its centre and half diagonal.
struct VolumeCell {
  Eigen::Vector3d center;
  double radius;
};
using Points = std::vector<VolumeCell>;
using Iterator = Points::iterator;

struct Capsule {
  Eigen::Vector3d a, b;  ///< ends of the axis (link frame)
  double radius = 0;
};

bool hasSphere(const Link& link, const Eigen::Vector3d& center, double radius) {
  for (const CollisionShape& s : link.shapes)
    if (s.type == CollisionShape::Type::kSphere && std::abs(s.size[0] - radius) <= 1e-9 &&
        (s.origin.translation() - center).norm() <= 1e-9)
      return true;
  return false;
}

/// The link's cylinders that carry a sphere of their radius on each end.
std::vector<Capsule> capsulesOf(const Link& link) {
  std::vector<Capsule> capsules;
  for (const CollisionShape& s : link.shapes) {
    if (s.type != CollisionShape::Type::kCylinder) continue;
    const Eigen::Vector3d half = s.origin.linear().col(2) * s.size[1] / 2;
    const Capsule c{s.origin.translation() - half, s.origin.translation() + half, s.size[0]};
    if (hasSphere(link, c.a, c.radius) && hasSphere(link, c.b, c.radius)) capsules.push_back(c);
  }
  return capsules;
}

/// The cells of a grid (spacing at most `spacing`) tiling the shape's
/// bounding box that may overlap the shape: together they hold it.
Points volumeCells(const CollisionShape& shape, double spacing) {
  const Eigen::Vector3d half = halfExtents(shape);
  Eigen::Vector3i cells;
  Eigen::Vector3d step;
  for (int a = 0; a < 3; ++a) {
    cells[a] = std::max(1, static_cast<int>(std::ceil(2 * half[a] / spacing)));
    step[a] = 2 * half[a] / cells[a];
  }
  const double cellRadius = step.norm() / 2;
  CollisionShape local = shape;
  local.origin = Eigen::Isometry3d::Identity();
  Points points;
  for (int i = 0; i < cells[0]; ++i)
    for (int j = 0; j < cells[1]; ++j)
      for (int k = 0; k < cells[2]; ++k) {
        const Eigen::Vector3d p =
            -half + Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5).cwiseProduct(step);
        if (signedDistance(local, p) <= cellRadius) points.push_back({p, cellRadius});
      }
  return points;
}

/// Covers a piece of a shape's volume grid (shape frame) and measures how far
/// the covering sphere reaches beyond the link.
class Piece {
 public:
  Piece(Iterator begin, Iterator end, const Link& link, const Eigen::Isometry3d& toLink)
      : begin_(begin), end_(end) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (auto p = begin; p != end; ++p) centroid += p->center;
    centroid /= static_cast<double>(end - begin);
    // Every point of every cell lies within the radius.
    double radius = 0;
    for (auto p = begin; p != end; ++p)
      radius = std::max(radius, (p->center - centroid).norm() + p->radius);
    sphere_.center = toLink * centroid;
    sphere_.radius = radius;
    excess_ = sphere_.radius + signedDistance(link, sphere_.center);
  }

  Iterator begin() const { return begin_; }
  Iterator end() const { return end_; }
  std::ptrdiff_t size() const { return end_ - begin_; }
  const LinkSphere& sphere() const { return sphere_; }
  double excess() const { return excess_; }

 private:
  Iterator begin_, end_;
  LinkSphere sphere_;
  double excess_ = 0;
};

class ShapeCoverer {
 public:
  ShapeCoverer(const Link& link, const CollisionShape& shape, double tolerance)
      : link_(link), to_link_(shape.origin), tolerance_(tolerance) {
    points_ = volumeCells(shape, tolerance / 4);
  }

  /// Adds the shape's sphere tree to `out` (its leaves to out.spheres);
  /// returns the index of its root node and raises out.excess to the
  /// largest excess among its leaves.
  int cover(LinkSpheres& out) { return build(piece(points_.begin(), points_.end()), out); }

 private:
  /// A leaf when the piece's sphere is tight enough, else a node over the
  /// trees of its two halves. The node's sphere covers every cell of the
  /// piece, so a query that misses it misses the whole subtree.
  int build(const Piece& current, LinkSpheres& out) {
    SphereNode node{current.sphere(), -1, -1};
    if (current.excess() <= tolerance_ || current.size() == 1) {
      out.spheres.push_back(current.sphere());
      out.excess = std::max(out.excess, current.excess());
    } else {
      const auto [first, second] = bestSplit(current);
      node.left = build(first, out);
      node.right = build(second, out);
    }
    out.tree.push_back(node);
    return static_cast<int>(out.tree.size()) - 1;
  }

  Piece piece(Iterator begin, Iterator end) const { return Piece(begin, end, link_, to_link_); }

  /// Splits at the median along the shape's x, y or z axis, whichever leaves
  /// the smaller worst excess (on a cylinder: slabs, not half discs).
  std::pair<Piece, Piece> bestSplit(const Piece& whole) const {
    const Iterator middle = whole.begin() + whole.size() / 2;
    int bestAxis = 0;
    double bestExcess = std::numeric_limits<double>::infinity();
    for (int axis = 0; axis < 3; ++axis) {
      splitAt(whole, middle, axis);
      const double excess =
          std::max(piece(whole.begin(), middle).excess(), piece(middle, whole.end()).excess());
      if (excess < bestExcess) {
        bestExcess = excess;
        bestAxis = axis;
      }
    }
    splitAt(whole, middle, bestAxis);
    return {piece(whole.begin(), middle), piece(middle, whole.end())};
  }

  static void splitAt(const Piece& whole, Iterator middle, int axis) {
    std::nth_element(
        whole.begin(), middle, whole.end(), [axis](const VolumeCell& ca, const VolumeCell& cb) {
          const Eigen::Vector3d &a = ca.center, &b = cb.center;
          return a[axis] < b[axis] ||
                 (a[axis] == b[axis] && std::tie(a[0], a[1], a[2]) < std::tie(b[0], b[1], b[2]));
        });
  }

  const Link& link_;
  Eigen::Isometry3d to_link_;
  double tolerance_;
  Points points_;
};

/// Covers a held body's surface (link_spheres.h, Link::mesh): its
/// triangles, split until no edge is longer than `edge`, are grouped by
/// halving them at the median of their centroids along the group's
/// longest extent until a group's sphere has at most `leafRadius`; every
/// node's sphere holds every vertex of its triangles, hence the triangles.
/// The surface is what FCL checks of a mesh, so the spheres hold it, not
/// the volume inside.
class MeshCoverer {
 public:
  MeshCoverer(const TriangleMesh& mesh, double tolerance) : leaf_radius_(tolerance / 2) {
    // A triangle's sphere about its centroid reaches at most 0.58 of its
    // longest edge: edges of 0.8 leaf radii keep one triangle a leaf.
    const double edge = 0.8 * leaf_radius_;
    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
      const auto corner = [&](int c) -> Eigen::Vector3d {
        return mesh.vertices.row(mesh.triangles(t, c)).transpose();
      };
      split({corner(0), corner(1), corner(2)}, edge);
    }
  }

  /// Adds the tree to `out` (leaves to out.spheres), returns its root and
  /// raises out.excess (at most twice a leaf's radius: a sphere's centre
  /// lies within its radius of a vertex).
  int cover(LinkSpheres& out) { return build(0, triangles_.size(), out); }

 private:
  using Triangle = std::array<Eigen::Vector3d, 3>;

  void split(const Triangle& t, double edge) {
    const double longest =
        std::max({(t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm()});
    if (longest <= edge) {
      triangles_.push_back(t);
      return;
    }
    const Eigen::Vector3d a = (t[0] + t[1]) / 2, b = (t[1] + t[2]) / 2, c = (t[2] + t[0]) / 2;
    split({t[0], a, c}, edge);
    split({a, t[1], b}, edge);
    split({c, b, t[2]}, edge);
    split({a, b, c}, edge);
  }

  static Eigen::Vector3d centroid(const Triangle& t) { return (t[0] + t[1] + t[2]) / 3; }

  LinkSphere sphereOf(std::size_t begin, std::size_t end) const {
    Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d high = -low;
    for (std::size_t i = begin; i < end; ++i)
      for (const Eigen::Vector3d& v : triangles_[i]) {
        low = low.cwiseMin(v);
        high = high.cwiseMax(v);
      }
    LinkSphere sphere{(low + high) / 2, 0.0};
    for (std::size_t i = begin; i < end; ++i)
      for (const Eigen::Vector3d& v : triangles_[i])
        sphere.radius = std::max(sphere.radius, (v - sphere.center).norm());
    return sphere;
  }

  int build(std::size_t begin, std::size_t end, LinkSpheres& out) {
    SphereNode node{sphereOf(begin, end), -1, -1};
    if (node.sphere.radius <= leaf_radius_ || end - begin == 1) {
      out.spheres.push_back(node.sphere);
      out.excess = std::max(out.excess, 2 * node.sphere.radius);
    } else {
      Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
      Eigen::Vector3d high = -low;
      for (std::size_t i = begin; i < end; ++i) {
        low = low.cwiseMin(centroid(triangles_[i]));
        high = high.cwiseMax(centroid(triangles_[i]));
      }
      Eigen::Index axis = 0;
      (high - low).maxCoeff(&axis);
      const std::size_t middle = begin + (end - begin) / 2;
      std::nth_element(triangles_.begin() + static_cast<std::ptrdiff_t>(begin),
                       triangles_.begin() + static_cast<std::ptrdiff_t>(middle),
                       triangles_.begin() + static_cast<std::ptrdiff_t>(end),
                       [axis](const Triangle& a, const Triangle& b) {
                         return centroid(a)[axis] < centroid(b)[axis];
                       });
      node.left = build(begin, middle, out);
      node.right = build(middle, end, out);
    }
    out.tree.push_back(node);
    return static_cast<int>(out.tree.size()) - 1;
  }

  double leaf_radius_;
  std::vector<Triangle> triangles_;
};

/// The smallest sphere that holds two spheres.
LinkSphere enclosing(const LinkSphere& a, const LinkSphere& b) {
  const double d = (b.center - a.center).norm();
  if (d + b.radius <= a.radius) return a;
  if (d + a.radius <= b.radius) return b;
  const double radius = (d + a.radius + b.radius) / 2;
  return {a.center + (radius - a.radius) / d * (b.center - a.center), radius};
}

}  // namespace

std::size_t SphereModel::numSpheres() const {
  std::size_t n = 0;
  for (const LinkSpheres& link : links) n += link.spheres.size();
  return n;
}

double SphereModel::maxExcess() const {
  double worst = 0;
  for (const LinkSpheres& link : links) worst = std::max(worst, link.excess);
  return worst;
}

double primitiveSignedDistance(CollisionShape::Type type, const Eigen::Vector3d& size,
                               const Eigen::Vector3d& p) {
  switch (type) {
    case CollisionShape::Type::kSphere:
      return p.norm() - size[0];
    case CollisionShape::Type::kBox: {
      const Eigen::Vector3d q = p.cwiseAbs() - size / 2;
      return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
    }
    case CollisionShape::Type::kCylinder: {
      const Eigen::Vector2d d(p.head<2>().norm() - size[0], std::abs(p.z()) - size[1] / 2);
      return d.cwiseMax(0.0).norm() + std::min(d.maxCoeff(), 0.0);
    }
  }
  return std::numeric_limits<double>::infinity();
}

double signedDistance(const CollisionShape& shape, const Eigen::Vector3d& point) {
  return primitiveSignedDistance(shape.type, shape.size, shape.origin.inverse() * point);
}

double signedDistance(const Link& link, const Eigen::Vector3d& point) {
  double distance = std::numeric_limits<double>::infinity();
  for (const CollisionShape& shape : link.shapes)
    distance = std::min(distance, signedDistance(shape, point));
  // A cylinder capped by two spheres of its radius is a capsule, whose depth
  // is exact (the minimum above underestimates it near the caps).
  for (const Capsule& capsule : capsulesOf(link)) {
    const Eigen::Vector3d axis = capsule.b - capsule.a;
    const double t = std::clamp((point - capsule.a).dot(axis) / axis.squaredNorm(), 0.0, 1.0);
    distance = std::min(distance, (point - capsule.a - t * axis).norm() - capsule.radius);
  }
  return distance;
}

LinkSpheres coverLink(const Link& link, const SphereModelOptions& options) {
  if (!(options.tolerance > 0) || !std::isfinite(options.tolerance))
    throw std::invalid_argument("sphere model tolerance must be positive and finite, got " +
                                std::to_string(options.tolerance));
  LinkSpheres result;
  // Joins a covered piece's tree (root `root`) to the link's.
  const auto join = [&result](int root) {
    if (result.root < 0) {
      result.root = root;
      return;
    }
    const LinkSphere& a = result.tree[static_cast<std::size_t>(result.root)].sphere;
    const LinkSphere& b = result.tree[static_cast<std::size_t>(root)].sphere;
    result.tree.push_back({enclosing(a, b), result.root, root});
    result.root = static_cast<int>(result.tree.size()) - 1;
  };
  for (const CollisionShape& shape : link.shapes) {
    int root = -1;
    if (shape.type == CollisionShape::Type::kSphere) {
      const LinkSphere sphere{shape.origin.translation(), shape.size[0]};
      result.spheres.push_back(sphere);
      result.tree.push_back({sphere, -1, -1});
      root = static_cast<int>(result.tree.size()) - 1;
    } else {
      // A thin shape (a flange, a plate) gets a tolerance of at most half
      // its thickness, so its spheres do not stand out further than it is
      // thick.
      const double thinnest = shape.type == CollisionShape::Type::kBox
                                  ? shape.size.minCoeff()
                                  : std::min(2 * shape.size[0], shape.size[1]);
      const double tolerance = std::min(options.tolerance, thinnest / 2);
      root = ShapeCoverer(link, shape, tolerance).cover(result);
    }
    join(root);
  }
  if (link.mesh != nullptr && link.mesh->triangles.rows() > 0)
    join(MeshCoverer(*link.mesh, options.tolerance).cover(result));
  return result;
}

SphereModel buildSphereModel(const RobotModel& model, const SphereModelOptions& options) {
  SphereModel result;
  for (const Link& link : model.links()) result.links.push_back(coverLink(link, options));
  return result;
}

}  // namespace hfts::robot
