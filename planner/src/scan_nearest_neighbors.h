#pragma once
// OMPL's nearest-neighbour interface over SIMD scans of the configurations
// (configuration_scan.h), in the weighted metric of Eq. (3). In the 13-D
// configuration space of the planner's trees, OMPL's GNAT evaluated about
// 900 distances per query through a std::function (a third of a long shelf
// plan). Here the configurations lie in columns, in insertion order, in
// blocks of 64 with a bounding box each; a query scans the block whose box
// is nearest, then every block whose box is not farther than the best
// distance so far: exact, and consecutive tree nodes are close to each
// other, so most blocks are skipped (docs/performance.md). Internal to the
// planner library.

#include <ompl/datastructures/NearestNeighbors.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "configuration_scan.h"
#include "robot/configuration_metric.h"

namespace hfts::planner {

/// `T` is a pointer to an element whose `q` member holds its configuration
/// (q.data(): metric.weights().size() doubles). Elements keep their
/// insertion order, so "the elements added since the k-th" is a suffix
/// (nearestDistance).
template <typename T>
class ScanNearestNeighbors : public ompl::NearestNeighbors<T> {
 public:
  /// The metric must outlive the structure; its weights are read at every
  /// query.
  explicit ScanNearestNeighbors(const robot::ConfigurationMetric& metric)
      : metric_(metric), dims_(static_cast<std::size_t>(metric.weights().size())) {}

  using ompl::NearestNeighbors<T>::add;

  bool reportsSortedResults() const override { return true; }
  void clear() override { items_.clear(); }  // add() starts the first block anew
  std::size_t size() const override { return items_.size(); }
  void list(std::vector<T>& data) const override { data = items_; }

  void add(const T& item) override {
    reserve(items_.size() + 1);
    const double* q = item->q.data();
    const std::size_t i = items_.size(), block = i / kBlock;
    for (std::size_t d = 0; d < dims_; ++d) {
      columns_[d * stride_ + i] = q[d];
      double& low = lo_[d * blockStride_ + block];
      double& high = hi_[d * blockStride_ + block];
      low = i % kBlock == 0 ? q[d] : std::min(low, q[d]);
      high = i % kBlock == 0 ? q[d] : std::max(high, q[d]);
    }
    items_.push_back(item);
  }

  /// Removes `item` keeping the others' order: O(size).
  bool remove(const T& item) override {
    const auto it = std::find(items_.begin(), items_.end(), item);
    if (it == items_.end()) return false;
    const auto index = static_cast<std::size_t>(it - items_.begin());
    for (std::size_t d = 0; d < dims_; ++d) {
      double* column = columns_.data() + d * stride_;
      std::copy(column + index + 1, column + items_.size(), column + index);
    }
    items_.erase(it);
    std::vector<T> kept;
    kept.swap(items_);
    for (const T& element : kept) add(element);  // the blocks' boxes anew
    return true;
  }

  /// The nearest element (the first added of equally near ones). Throws
  /// std::logic_error when empty.
  T nearest(const T& item) const override {
    if (items_.empty()) throw std::logic_error("nearest neighbour of an empty set");
    return items_[search(item->q.data(), 0).index];
  }

  void nearestK(const T& item, std::size_t k, std::vector<T>& nbh) const override {
    std::vector<std::size_t> order = sortedByDistance(item->q.data());
    order.resize(std::min(k, order.size()));
    nbh.clear();
    for (const std::size_t i : order) nbh.push_back(items_[i]);
  }

  void nearestR(const T& item, double radius, std::vector<T>& nbh) const override {
    const std::vector<std::size_t> order = sortedByDistance(item->q.data());
    nbh.clear();
    for (const std::size_t i : order) {
      if (squared_[i] > radius * radius) break;
      nbh.push_back(items_[i]);
    }
  }

  /// The smallest distance from q (dims doubles) to the elements added
  /// from the `first`-th on; +infinity when there are none.
  double nearestDistance(const double* q, std::size_t first = 0) const {
    if (first >= items_.size()) return std::numeric_limits<double>::infinity();
    return std::sqrt(search(q, first).squared);
  }

 private:
  static constexpr std::size_t kBlock = 64;

  /// The nearest of the elements [first, size()) (the first of equally
  /// near ones); size() > first.
  scan::Nearest search(const double* q, std::size_t first) const {
    const double* w = metric_.weights().data();
    const std::size_t end = items_.size();
    scan::Nearest best{end, std::numeric_limits<double>::infinity()};
    auto visit = [&](std::size_t begin, std::size_t stop) {
      const scan::Nearest found = scan::nearest(columns_.data(), stride_, dims_, begin, stop, q, w);
      if (found.squared < best.squared ||
          (found.squared == best.squared && found.index < best.index))
        best = found;
    };
    std::size_t block = first / kBlock;
    if (first % kBlock != 0) visit(first, std::min(end, ++block * kBlock));  // a partial block
    const std::size_t blocks = (end + kBlock - 1) / kBlock;
    if (block >= blocks) return best;
    const std::size_t count = blocks - block;
    bounds_.resize(count);
    scan::boxLowerBounds(lo_.data() + block, hi_.data() + block, blockStride_, dims_, count, q, w,
                         bounds_.data());
    const std::size_t nearestBox = static_cast<std::size_t>(
        std::min_element(bounds_.begin(), bounds_.end()) - bounds_.begin());
    auto range = [&](std::size_t b) {
      visit((block + b) * kBlock, std::min(end, (block + b + 1) * kBlock));
    };
    range(nearestBox);
    for (std::size_t b = 0; b < count; ++b)
      if (b != nearestBox && !(bounds_[b] > best.squared)) range(b);
    return best;
  }

  /// Room for `count` elements plus a vector's worth past the end (the
  /// scan loads whole vectors).
  void reserve(std::size_t count) {
    constexpr std::size_t kPad = 16;
    const std::size_t blocks = (count + kBlock - 1) / kBlock;
    if (blocks + kPad > blockStride_) {
      const std::size_t stride = std::max<std::size_t>(2 * blockStride_, blocks + kPad + 16);
      auto grow = [&](std::vector<double>& boxes) {
        std::vector<double> wider(dims_ * stride, 0.0);
        for (std::size_t d = 0; d < dims_; ++d)
          std::copy(boxes.begin() + static_cast<std::ptrdiff_t>(d * blockStride_),
                    boxes.begin() + static_cast<std::ptrdiff_t>((d + 1) * blockStride_),
                    wider.begin() + static_cast<std::ptrdiff_t>(d * stride));
        boxes = std::move(wider);
      };
      grow(lo_);
      grow(hi_);
      blockStride_ = stride;
    }
    if (count + kPad <= stride_) return;
    const std::size_t stride = std::max<std::size_t>(2 * stride_, count + kPad + 64);
    std::vector<double> columns(dims_ * stride, 0.0);
    for (std::size_t d = 0; d < dims_; ++d)
      std::copy(columns_.begin() + static_cast<std::ptrdiff_t>(d * stride_),
                columns_.begin() + static_cast<std::ptrdiff_t>(d * stride_ + items_.size()),
                columns.begin() + static_cast<std::ptrdiff_t>(d * stride));
    columns_ = std::move(columns);
    stride_ = stride;
  }

  std::vector<std::size_t> sortedByDistance(const double* q) const {
    squared_.resize(items_.size());
    if (!items_.empty())
      scan::squaredDistances(columns_.data(), stride_, dims_, 0, items_.size(), q,
                             metric_.weights().data(), squared_.data());
    std::vector<std::size_t> order(items_.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return squared_[a] < squared_[b]; });
    return order;
  }

  const robot::ConfigurationMetric& metric_;
  std::size_t dims_;
  std::vector<T> items_;
  std::vector<double> columns_;  ///< DoF d of element i at d * stride_ + i
  std::size_t stride_ = 0;
  std::vector<double> lo_, hi_;  ///< each block's box: DoF d of block b at d * blockStride_ + b
  std::size_t blockStride_ = 0;
  mutable std::vector<double> squared_;  ///< scratch of nearestK / nearestR
  mutable std::vector<double> bounds_;   ///< scratch of search
};

}  // namespace hfts::planner
