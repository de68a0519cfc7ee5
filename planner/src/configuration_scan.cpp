// Compiled once per SIMD target through Highway's foreach_target; the
// functions of configuration_scan.h dispatch to the best one the CPU has.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "configuration_scan.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <limits>

#include "configuration_scan.h"

HWY_BEFORE_NAMESPACE();
namespace hfts::planner::scan {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;

/// Squared distances of the points [i, i + lanes) (lanes past `end` +inf).
HWY_INLINE V distancesAt(D d, const double* data, std::size_t stride, std::size_t dims,
                         std::size_t i, std::size_t end, const double* q, const double* weights) {
  V sum = hn::Zero(d);
  for (std::size_t k = 0; k < dims; ++k) {
    const V diff = hn::Sub(hn::LoadU(d, data + k * stride + i), hn::Set(d, q[k]));
    sum = hn::MulAdd(hn::Mul(hn::Set(d, weights[k]), diff), diff, sum);
  }
  if (end - i >= hn::Lanes(d)) return sum;
  return hn::IfThenElse(hn::FirstN(d, end - i), sum,
                        hn::Set(d, std::numeric_limits<double>::infinity()));
}

Nearest NearestImpl(const double* data, std::size_t stride, std::size_t dims, std::size_t begin,
                    std::size_t end, const double* q, const double* weights) {
  const D d;
  const std::size_t n = hn::Lanes(d);
  // Per lane: the smallest distance so far and the index of its point.
  V best = hn::Set(d, std::numeric_limits<double>::infinity());
  V bestIndex = hn::Zero(d);
  V index = hn::Iota(d, static_cast<double>(begin));
  const V step = hn::Set(d, static_cast<double>(n));
  for (std::size_t i = begin; i < end; i += n) {
    const V distance = distancesAt(d, data, stride, dims, i, end, q, weights);
    const auto closer = hn::Lt(distance, best);  // strict: the first of equals stays
    best = hn::IfThenElse(closer, distance, best);
    bestIndex = hn::IfThenElse(closer, index, bestIndex);
    index = hn::Add(index, step);
  }
  alignas(64) double values[16], indices[16];
  hn::Store(best, d, values);
  hn::Store(bestIndex, d, indices);
  Nearest out{end, std::numeric_limits<double>::infinity()};
  for (std::size_t k = 0; k < n; ++k) {
    const auto at = static_cast<std::size_t>(indices[k]);
    if (values[k] < out.squared || (values[k] == out.squared && at < out.index))
      out = {at, values[k]};
  }
  if (out.index == end) out = {begin, out.squared};  // every distance +inf or NaN
  return out;
}

void SquaredDistancesImpl(const double* data, std::size_t stride, std::size_t dims,
                          std::size_t begin, std::size_t end, const double* q,
                          const double* weights, double* out) {
  const D d;
  const std::size_t n = hn::Lanes(d);
  for (std::size_t i = begin; i < end; i += n) {
    const V distance = distancesAt(d, data, stride, dims, i, end, q, weights);
    if (end - i >= n) {
      hn::StoreU(distance, d, out + (i - begin));
    } else {
      alignas(64) double tail[16];
      hn::Store(distance, d, tail);
      for (std::size_t k = 0; k < end - i; ++k) out[i - begin + k] = tail[k];
    }
  }
}

void BoxLowerBoundsImpl(const double* lo, const double* hi, std::size_t stride, std::size_t dims,
                        std::size_t count, const double* q, const double* weights, double* out) {
  const D d;
  const std::size_t n = hn::Lanes(d);
  for (std::size_t b = 0; b < count; b += n) {
    V sum = hn::Zero(d);
    for (std::size_t k = 0; k < dims; ++k) {
      const V value = hn::Set(d, q[k]);
      // How far q lies outside [lo, hi] along this DoF (0 inside).
      const V gap = hn::Max(hn::Max(hn::Sub(hn::LoadU(d, lo + k * stride + b), value),
                                    hn::Sub(value, hn::LoadU(d, hi + k * stride + b))),
                            hn::Zero(d));
      sum = hn::MulAdd(hn::Mul(hn::Set(d, weights[k]), gap), gap, sum);
    }
    if (count - b >= n) {
      hn::StoreU(sum, d, out + b);
    } else {
      alignas(64) double tail[16];
      hn::Store(sum, d, tail);
      for (std::size_t k = 0; k < count - b; ++k) out[b + k] = tail[k];
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace hfts::planner::scan
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace hfts::planner::scan {

HWY_EXPORT(NearestImpl);
HWY_EXPORT(SquaredDistancesImpl);
HWY_EXPORT(BoxLowerBoundsImpl);

Nearest nearest(const double* data, std::size_t stride, std::size_t dims, std::size_t begin,
                std::size_t end, const double* q, const double* weights) {
  return HWY_DYNAMIC_DISPATCH(NearestImpl)(data, stride, dims, begin, end, q, weights);
}

void squaredDistances(const double* data, std::size_t stride, std::size_t dims, std::size_t begin,
                      std::size_t end, const double* q, const double* weights, double* out) {
  HWY_DYNAMIC_DISPATCH(SquaredDistancesImpl)(data, stride, dims, begin, end, q, weights, out);
}

void boxLowerBounds(const double* lo, const double* hi, std::size_t stride, std::size_t dims,
                    std::size_t count, const double* q, const double* weights, double* out) {
  HWY_DYNAMIC_DISPATCH(BoxLowerBoundsImpl)(lo, hi, stride, dims, count, q, weights, out);
}

}  // namespace hfts::planner::scan
#endif
