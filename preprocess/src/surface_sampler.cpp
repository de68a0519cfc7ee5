// Visibility-tested surface sampling with Embree.
#include "preprocess/surface_sampler.h"

#include "hfts_db/triangle_bvh.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace hfts::preprocess {
namespace {

/// Directions closer to the surface plane than this are not used: a
/// grazing ray says little about visibility and is numerically fragile.
constexpr double kMinCosine = 0.05;

Eigen::Vector3d vertex(const TriangleMesh& mesh, std::uint32_t face, int k) {
  return mesh.vertices.row(mesh.triangles(face, k)).transpose();
}

/// Stratified area-uniform points: stratum i of the cumulative area picks
/// the triangle, a uniform barycentric draw the point inside it.
void drawCandidates(const TriangleMesh& mesh, std::size_t count, std::mt19937_64& rng,
                    std::vector<std::uint32_t>& faces, Vertices& points) {
  std::vector<double> cumulative(static_cast<std::size_t>(mesh.triangles.rows()));
  double total = 0.0;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const auto f = static_cast<std::uint32_t>(t);
    total += 0.5 * (vertex(mesh, f, 1) - vertex(mesh, f, 0))
                       .cross(vertex(mesh, f, 2) - vertex(mesh, f, 0))
                       .norm();
    cumulative[static_cast<std::size_t>(t)] = total;
  }
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  faces.resize(count);
  points.resize(static_cast<Eigen::Index>(count), 3);
  for (std::size_t i = 0; i < count; ++i) {
    const double u = (static_cast<double>(i) + uniform(rng)) / static_cast<double>(count) * total;
    const auto it = std::lower_bound(cumulative.begin(), cumulative.end(), u);
    const auto f = static_cast<std::uint32_t>(
        std::min<std::ptrdiff_t>(it - cumulative.begin(), mesh.triangles.rows() - 1));
    double a = uniform(rng);
    double b = uniform(rng);
    if (a + b > 1.0) {
      a = 1.0 - a;
      b = 1.0 - b;
    }
    faces[i] = f;
    points.row(static_cast<Eigen::Index>(i)) =
        (vertex(mesh, f, 0) + a * (vertex(mesh, f, 1) - vertex(mesh, f, 0)) +
         b * (vertex(mesh, f, 2) - vertex(mesh, f, 0)))
            .transpose();
  }
}

bool visibleAlong(const db::TriangleBvh& scene, const Vertices& directions,
                  const Eigen::Vector3d& p, const Eigen::Vector3d& side, double offset) {
  const Eigen::Vector3d origin = p + offset * side;
  if (scene.escapes(origin, side)) return true;
  for (Eigen::Index d = 0; d < directions.rows(); ++d) {
    const Eigen::Vector3d dir = directions.row(d).transpose();
    if (dir.dot(side) > kMinCosine && scene.escapes(origin, dir)) return true;
  }
  return false;
}

}  // namespace

Vertices fibonacciSphere(std::uint32_t count) {
  Vertices directions(count, 3);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (std::uint32_t i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / count;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    directions.row(i) << r * std::cos(golden * i), r * std::sin(golden * i), z;
  }
  return directions;
}

SurfaceSamples sampleVisibleSurface(const TriangleMesh& mesh, const SamplingOptions& options) {
  if (!(options.density > 0.0) || !std::isfinite(options.density))
    throw std::invalid_argument("sample density must be a positive number of points per m^2");
  if (options.max_samples == 0) throw std::invalid_argument("max_samples must be at least 1");
  if (options.viewpoints < 8) throw std::invalid_argument("viewpoints must be at least 8");

  const double area = surfaceArea(mesh);
  const auto wanted = static_cast<std::size_t>(std::llround(options.density * area));
  const std::size_t count = std::clamp<std::size_t>(wanted, 1, options.max_samples);

  std::mt19937_64 rng(options.seed);
  std::vector<std::uint32_t> faces;
  Vertices candidates;
  drawCandidates(mesh, count, rng, faces, candidates);

  const db::TriangleBvh scene(mesh);
  const Vertices directions = fibonacciSphere(options.viewpoints);
  const double extent =
      (mesh.vertices.colwise().maxCoeff() - mesh.vertices.colwise().minCoeff()).norm();
  const double offset = 1e-5 * extent;

  SurfaceSamples out;
  out.candidates = count;
  std::vector<Eigen::Vector3d> positions, normals;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t f = faces[i];
    const Eigen::Vector3d n = (vertex(mesh, f, 1) - vertex(mesh, f, 0))
                                  .cross(vertex(mesh, f, 2) - vertex(mesh, f, 0))
                                  .normalized();
    const Eigen::Vector3d p = candidates.row(static_cast<Eigen::Index>(i)).transpose();
    for (const double sign : {1.0, -1.0}) {
      if (!visibleAlong(scene, directions, p, sign * n, offset)) continue;
      positions.push_back(p);
      normals.push_back(sign * n);
      out.faces.push_back(f);
    }
  }
  out.positions.resize(static_cast<Eigen::Index>(positions.size()), 3);
  out.normals.resize(static_cast<Eigen::Index>(normals.size()), 3);
  for (std::size_t i = 0; i < positions.size(); ++i) {
    out.positions.row(static_cast<Eigen::Index>(i)) = positions[i].transpose();
    out.normals.row(static_cast<Eigen::Index>(i)) = normals[i].transpose();
  }
  return out;
}

SurfaceSamples supportSamples(const TriangleMesh& mesh, const SurfaceSamples& contacts,
                              double patchRadius, const SamplingOptions& options) {
  if (!(patchRadius > 0.0) || !std::isfinite(patchRadius))
    throw std::invalid_argument("the patch radius must be a positive number of metres");
  const double drawn = static_cast<double>(contacts.candidates) / surfaceArea(mesh);
  const double wanted = kSupportPerPatch / (M_PI * patchRadius * patchRadius);
  if (drawn >= wanted) return contacts;
  SamplingOptions dense = options;
  dense.density = wanted;
  dense.max_samples = kMaxSupportSamples;
  dense.seed = options.seed + 1;
  return sampleVisibleSurface(mesh, dense);
}

}  // namespace hfts::preprocess
