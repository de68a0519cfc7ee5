#pragma once
// Nearest configuration by a linear scan in SIMD (Highway; the widest
// vectors the CPU offers, chosen at run time), in the weighted metric of
// Eq. (3). Internal to the planner library (scan_nearest_neighbors.h).

#include <cstddef>

namespace hfts::planner::scan {

struct Nearest {
  std::size_t index = 0;
  double squared = 0.0;  ///< squared weighted distance
};

/// Points are stored a DoF per column: DoF d of point i at
/// data[d * stride + i]. Returns the point of [begin, end) nearest to q
/// (the first of equally near ones) in sqrt(sum_d w_d (p_d - q_d)^2).
/// Requires begin < end <= stride.
Nearest nearest(const double* data, std::size_t stride, std::size_t dims, std::size_t begin,
                std::size_t end, const double* q, const double* weights);

/// The squared weighted distances of the points [begin, end) to q, into
/// out[0 .. end - begin).
void squaredDistances(const double* data, std::size_t stride, std::size_t dims, std::size_t begin,
                      std::size_t end, const double* q, const double* weights, double* out);

/// Lower bounds of the squared weighted distance from q to the boxes
/// [lo, hi] (DoF d of box b at lo[d * stride + b]) of boxes [0, count),
/// into out[0 .. count).
void boxLowerBounds(const double* lo, const double* hi, std::size_t stride, std::size_t dims,
                    std::size_t count, const double* q, const double* weights, double* out);

}  // namespace hfts::planner::scan
