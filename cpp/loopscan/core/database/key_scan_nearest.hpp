#pragma once
// The result set of one query key of a KeyScan: candidates at or below the bound are appended
// and the buffer is cut back to the `count` best whenever it holds 2 count (amortised O(1) a
// place; a heap costs O(log count) each). Ties go to the smaller id.
#include <algorithm>
#include <cstdint>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

namespace loopscan::key_scan {

class Nearest {
 public:
  Nearest(std::size_t count, const std::function<bool(std::size_t)>& eligible)
      : count_(count), eligible_(&eligible) {
    items_.reserve(2 * count + 1);
  }
  std::uint32_t bound() const { return bound_; }
  void add(std::uint32_t dist, std::uint32_t id) {
    if (dist > bound_ || !(*eligible_)(id)) return;
    items_.emplace_back(dist, id);
    if (items_.size() == count_) {
      bound_ = std::max_element(items_.begin(), items_.end())->first;
    } else if (items_.size() >= 2 * count_) {
      cut();
    }
  }
  void finish(std::vector<std::pair<std::uint32_t, std::size_t>>& out) {
    if (items_.size() > count_) cut();
    std::sort(items_.begin(), items_.end());
    out.swap(items_);
  }

 private:
  void cut() {
    std::nth_element(items_.begin(), items_.begin() + (count_ - 1), items_.end());
    items_.resize(count_);
    bound_ = items_.back().first;  // the count-th distance: nth_element put it last
  }
  std::size_t count_;
  std::uint32_t bound_ = std::numeric_limits<std::uint32_t>::max();
  const std::function<bool(std::size_t)>* eligible_;
  std::vector<std::pair<std::uint32_t, std::size_t>> items_;
};

}  // namespace loopscan::key_scan
