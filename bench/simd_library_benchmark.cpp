// Which SIMD library for the sphere tier (issue 16: "Highway, xsimd or
// Eigen arrays; measure which")? The tier's innermost test, spheres
// against a rotated box, written three ways on the same data: plain
// scalar code, Eigen arrays (vectorised for the build's target ISA) and
// Highway (compiled for every target, dispatched at run time). Each
// benchmark counts the spheres that touch, and the three counts must agree.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "simd_library_benchmark.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/aligned_allocator.h>
#include <hwy/highway.h>

#include <cstddef>
#include <cstdint>

// Per-target code: the Highway variant.
HWY_BEFORE_NAMESPACE();
namespace simd_bench {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

std::size_t CountTouchingImpl(const float* x, const float* y, const float* z, const float* r,
                              std::size_t count, const float* rotation, const float* translation,
                              const float* half) {
  const hn::ScalableTag<float> d;
  const std::size_t n = hn::Lanes(d);
  std::size_t touching = 0;
  for (std::size_t i = 0; i + n <= count; i += n) {
    const auto cx = hn::Load(d, x + i), cy = hn::Load(d, y + i), cz = hn::Load(d, z + i);
    const auto radius = hn::Load(d, r + i);
    auto outside = hn::Zero(d);
    for (int row = 0; row < 3; ++row) {
      const float* R = rotation + 3 * row;
      const auto p =
          hn::MulAdd(hn::Set(d, R[0]), cx,
                     hn::MulAdd(hn::Set(d, R[1]), cy,
                                hn::MulAdd(hn::Set(d, R[2]), cz, hn::Set(d, translation[row]))));
      const auto q = hn::Max(hn::Sub(hn::Abs(p), hn::Set(d, half[row])), hn::Zero(d));
      outside = hn::MulAdd(q, q, outside);
    }
    touching += hn::CountTrue(d, hn::Le(outside, hn::Mul(radius, radius)));
  }
  return touching;
}

}  // namespace HWY_NAMESPACE
}  // namespace simd_bench
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

namespace simd_bench {
HWY_EXPORT(CountTouchingImpl);

namespace {

constexpr std::size_t kSpheres = 4096;  // a multiple of every vector width

/// Sphere centres in a 1 m cube around a 0.6 x 0.4 x 0.05 m box turned
/// about z and x; radii 1-5 cm (like the leaves of the link sphere trees).
struct Scene {
  hwy::AlignedFreeUniquePtr<float[]> x, y, z, r;
  float rotation[9];
  float translation[3] = {-0.1f, 0.05f, 0.02f};
  float half[3] = {0.3f, 0.2f, 0.025f};
  Scene()
      : x(hwy::AllocateAligned<float>(kSpheres)),
        y(hwy::AllocateAligned<float>(kSpheres)),
        z(hwy::AllocateAligned<float>(kSpheres)),
        r(hwy::AllocateAligned<float>(kSpheres)) {
    std::mt19937 random(7);
    std::uniform_real_distribution<float> position(-0.5f, 0.5f), radius(0.01f, 0.05f);
    for (std::size_t i = 0; i < kSpheres; ++i) {
      x[i] = position(random);
      y[i] = position(random);
      z[i] = position(random) * 0.3f;
      r[i] = radius(random);
    }
    const Eigen::Matrix3f m = (Eigen::AngleAxisf(0.4f, Eigen::Vector3f::UnitZ()) *
                               Eigen::AngleAxisf(0.2f, Eigen::Vector3f::UnitX()))
                                  .toRotationMatrix();
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 3; ++col) rotation[3 * row + col] = m(row, col);
  }
};

const Scene& scene() {
  static const Scene s;
  return s;
}

std::size_t countScalar(const Scene& s) {
  std::size_t touching = 0;
  for (std::size_t i = 0; i < kSpheres; ++i) {
    float outside = 0.0f;
    for (int row = 0; row < 3; ++row) {
      const float* R = s.rotation + 3 * row;
      const float p = R[0] * s.x[i] + R[1] * s.y[i] + R[2] * s.z[i] + s.translation[row];
      const float q = std::max(std::abs(p) - s.half[row], 0.0f);
      outside += q * q;
    }
    touching += outside <= s.r[i] * s.r[i] ? 1 : 0;
  }
  return touching;
}

std::size_t countEigen(const Scene& s) {
  using Array = Eigen::Map<const Eigen::ArrayXf, Eigen::Aligned64>;
  const Array x(s.x.get(), kSpheres), y(s.y.get(), kSpheres), z(s.z.get(), kSpheres),
      r(s.r.get(), kSpheres);
  Eigen::ArrayXf outside = Eigen::ArrayXf::Zero(kSpheres);
  for (int row = 0; row < 3; ++row) {
    const float* R = s.rotation + 3 * row;
    const Eigen::ArrayXf q =
        ((R[0] * x + R[1] * y + R[2] * z + s.translation[row]).abs() - s.half[row]).max(0.0f);
    outside += q * q;
  }
  return static_cast<std::size_t>((outside <= r * r).count());
}

std::size_t countHighway(const Scene& s) {
  return HWY_DYNAMIC_DISPATCH(CountTouchingImpl)(s.x.get(), s.y.get(), s.z.get(), s.r.get(),
                                                 kSpheres, s.rotation, s.translation, s.half);
}

template <std::size_t (*Count)(const Scene&)>
void BM_SpheresAgainstBox(benchmark::State& state) {
  const Scene& s = scene();
  const std::size_t expected = countScalar(s);
  std::size_t touching = 0;
  for (auto _ : state) {
    touching = Count(s);
    benchmark::DoNotOptimize(touching);
  }
  if (touching != expected) state.SkipWithError("the count differs from the scalar code's");
  state.counters["touching"] = static_cast<double>(touching);
  state.counters["ns_per_sphere"] = benchmark::Counter(
      static_cast<double>(kSpheres),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

BENCHMARK(BM_SpheresAgainstBox<countScalar>)->Name("BM_SpheresAgainstBox/scalar");
BENCHMARK(BM_SpheresAgainstBox<countEigen>)->Name("BM_SpheresAgainstBox/eigen_arrays");
BENCHMARK(BM_SpheresAgainstBox<countHighway>)->Name("BM_SpheresAgainstBox/highway");

}  // namespace
}  // namespace simd_bench

BENCHMARK_MAIN();
#endif  // HWY_ONCE
