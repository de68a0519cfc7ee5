// Compiled once per SIMD target through Highway's foreach_target.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "sin_cos.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/contrib/math/math-inl.h>
#include <hwy/highway.h>

#include "sin_cos.h"

HWY_BEFORE_NAMESPACE();
namespace hfts::robot {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void SinCosImpl(const double* angles, std::size_t count, double* sines, double* cosines) {
  const hn::ScalableTag<double> d;
  const std::size_t n = hn::Lanes(d);
  alignas(64) double in[16] = {}, s[16], c[16];
  for (std::size_t i = 0; i < count; i += n) {
    const std::size_t chunk = count - i < n ? count - i : n;
    for (std::size_t k = 0; k < chunk; ++k) in[k] = angles[i + k];
    const auto v = hn::Load(d, in);
    hn::Store(hn::Sin(d, v), d, s);
    hn::Store(hn::Cos(d, v), d, c);
    for (std::size_t k = 0; k < chunk; ++k) {
      sines[i + k] = s[k];
      cosines[i + k] = c[k];
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace hfts::robot
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace hfts::robot {

HWY_EXPORT(SinCosImpl);

void sinCos(const double* angles, std::size_t count, double* sines, double* cosines) {
  HWY_DYNAMIC_DISPATCH(SinCosImpl)(angles, count, sines, cosines);
}

}  // namespace hfts::robot
#endif
