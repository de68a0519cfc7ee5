#pragma once
// Area-uniform sampling of the externally visible surface (Embree).

#include <cstdint>

#include "hfts_db/triangle_mesh.h"

namespace hfts::preprocess {

struct SamplingOptions {
  double density = 200000.0;          ///< samples per square metre of mesh surface
  std::uint32_t max_samples = 20000;  ///< cap on the candidates drawn
  std::uint32_t viewpoints = 64;      ///< Fibonacci-sphere directions of the visibility test
  std::uint64_t seed = 1;
};

/// Samples on the surface with the side they are seen from.
struct SurfaceSamples {
  Vertices positions;
  Vertices normals;  ///< face normals, oriented towards the side the sample is seen from
  std::vector<std::uint32_t> faces;  ///< triangle of each sample
  std::size_t candidates = 0;        ///< area-uniform points drawn before the visibility test
};

/// Draws min(max_samples, density * area) stratified, area-uniform points on
/// the triangles, then keeps each side of each point that is visible from at
/// least one viewpoint at infinity (a ray from the point towards one of the
/// `viewpoints` Fibonacci-sphere directions escapes the mesh; Embree BVH).
/// Internal faces and closed cavities are seen from nowhere and yield no
/// samples; a thin open sheet seen from both sides yields both sides.
/// Deterministic for a given seed. Throws std::invalid_argument for bad
/// options and std::runtime_error if Embree fails.
SurfaceSamples sampleVisibleSurface(const TriangleMesh& mesh, const SamplingOptions& options);

/// Samples a patch of normal estimation should hold (estimateNormals'
/// support): over ten points a fitted plane tells an edge from a face by
/// chance, over forty reliably.
inline constexpr double kSupportPerPatch = 40.0;
/// At most this many support samples (2 x 2 m of surface at 4 mm patches).
inline constexpr std::uint32_t kMaxSupportSamples = 500000;

/// The points normals are fitted to: `contacts` themselves if they were
/// drawn densely enough to put kSupportPerPatch of them in a disc of radius
/// `patchRadius`, else a denser visible sampling of the same surface with
/// the same options but that density, at most kMaxSupportSamples and seed
/// options.seed + 1.
SurfaceSamples supportSamples(const TriangleMesh& mesh, const SurfaceSamples& contacts,
                              double patchRadius, const SamplingOptions& options);

/// `count` unit directions spread evenly over the sphere (Fibonacci lattice).
Vertices fibonacciSphere(std::uint32_t count);

}  // namespace hfts::preprocess
