#include "robot/depth_renderer.h"

#include <cmath>
#include <random>
#include <string>

#include "core/invalid_argument.h"
#include "glb_builder.h"
#include "hfts_db/triangle_bvh.h"

namespace hfts::robot {
namespace {

using glb::primitiveMesh;
using glb::transformed;

/// The scene's surfaces in the world as one mesh, and how many of its
/// triangles (the first ones) are the obstacles'.
struct World {
  TriangleMesh mesh;
  Eigen::Index obstacleTriangles = 0;
};

void append(TriangleMesh& into, const TriangleMesh& part) {
  const Eigen::Index v = into.vertices.rows(), t = into.triangles.rows();
  into.vertices.conservativeResize(v + part.vertices.rows(), 3);
  into.vertices.bottomRows(part.vertices.rows()) = part.vertices;
  into.triangles.conservativeResize(t + part.triangles.rows(), 3);
  into.triangles.bottomRows(part.triangles.rows()) =
      part.triangles.array() + static_cast<std::uint32_t>(v);
}

World worldOf(const Scene& scene, const TriangleMesh* target, const Eigen::Isometry3d& targetPose) {
  World world;
  for (const Obstacle& o : scene.obstacles) {
    const bool meshed = o.type == Obstacle::Type::kMesh || o.type == Obstacle::Type::kPoints;
    append(world.mesh,
           transformed(meshed ? o.mesh : primitiveMesh(static_cast<int>(o.type), o.size), o.pose));
  }
  world.obstacleTriangles = world.mesh.triangles.rows();
  if (target != nullptr) append(world.mesh, transformed(*target, targetPose));
  return world;
}

}  // namespace

DepthView DepthView::withFieldOfView(int width, int height, double fov) {
  DepthView view;
  view.width = width;
  view.height = height;
  view.camera.fx = view.camera.fy = 0.5 * width / std::tan(0.5 * fov);
  view.camera.cx = 0.5 * (width - 1);
  view.camera.cy = 0.5 * (height - 1);
  return view;
}

Eigen::Isometry3d lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& centre) {
  const Eigen::Vector3d z = (centre - eye).normalized();
  // Image rows go down the world where they can; straight down, along -y.
  Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
  if (x.norm() < 1e-6) x = Eigen::Vector3d::UnitX();
  x.normalize();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() << x, z.cross(x), z;
  pose.translation() = eye;
  return pose;
}

RenderedDepth renderDepth(const Scene& scene, const TriangleMesh* target,
                          const Eigen::Isometry3d& targetPose, const DepthView& view,
                          const DepthNoise& noise) {
  if (view.width <= 0 || view.height <= 0 || view.width > 4096 || view.height > 4096)
    throw InvalidArgument("view", "must be 1 to 4096 pixels wide and high");
  if (!(view.camera.fx > 0.0) || !(view.camera.fy > 0.0))
    throw InvalidArgument("view", "needs positive focal lengths");
  const World world = worldOf(scene, target, targetPose);
  RenderedDepth out;
  out.image.width = view.width;
  out.image.height = view.height;
  out.image.depths.assign(std::size_t(view.width) * std::size_t(view.height), 0.0f);
  out.target_mask.assign(out.image.depths.size(), 0);
  if (world.mesh.triangles.rows() == 0) return out;
  const db::TriangleBvh bvh(world.mesh);
  std::mt19937_64 rng(noise.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double minCosine = std::cos(std::min(noise.max_incidence, 0.5 * 3.14159265358979323846));
  const Eigen::Vector3d eye = view.pose.translation();
  for (int v = 0; v < view.height; ++v)
    for (int u = 0; u < view.width; ++u) {
      const Eigen::Vector3d ray((u - view.camera.cx) / view.camera.fx,
                                (v - view.camera.cy) / view.camera.fy, 1.0);
      const Eigen::Vector3d direction = view.pose.linear() * ray;  // unit depth along the view
      const std::optional<db::RayHit> hit = bvh.firstHit(eye, direction);
      // Every pixel draws its noise, seen or not, so one pixel's noise does
      // not depend on what the others see.
      const double n = gauss(rng), lost = uniform(rng);
      if (!hit) continue;
      const std::size_t pixel = std::size_t(v) * std::size_t(view.width) + std::size_t(u);
      const auto t = static_cast<Eigen::Index>(hit->triangle);
      out.target_mask[pixel] = t >= world.obstacleTriangles ? 1 : 0;
      const Eigen::Vector3d a = world.mesh.vertices.row(world.mesh.triangles(t, 0)),
                            b = world.mesh.vertices.row(world.mesh.triangles(t, 1)),
                            c = world.mesh.vertices.row(world.mesh.triangles(t, 2));
      const Eigen::Vector3d normal = (b - a).cross(c - a).normalized();
      if (std::abs(normal.dot(direction.normalized())) < minCosine || lost < noise.dropout)
        continue;
      const double z = hit->distance;  // the direction has unit depth
      const double sigma = noise.sigma_base + noise.sigma_quadratic * (z - noise.sigma_centre) *
                                                  (z - noise.sigma_centre);
      const double depth = z + sigma * n;
      if (depth < view.camera.min_depth || depth > view.camera.max_depth) continue;
      out.image.depths[pixel] = static_cast<float>(depth);
    }
  return out;
}

}  // namespace hfts::robot
