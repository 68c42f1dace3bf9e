#pragma once
// The `count` nearest eligible places of one query (KeyScan, and KeyIndex's tree searches):
// candidates at or below the bound are appended and the buffer is cut back to the `count`
// best whenever it holds 2 count (amortised O(1) a place; a heap costs O(log count) each,
// which dominated searches for hundreds of neighbours). Ties go to the smaller index.
#include <algorithm>
#include <cstddef>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

namespace loopscan {

template <class Distance>
class NearestSet {
 public:
  using Items = std::vector<std::pair<Distance, std::size_t>>;
  NearestSet(std::size_t count, const std::function<bool(std::size_t)>& eligible)
      : count_(count), eligible_(&eligible) {
    items_.reserve(2 * count + 1);
  }
  Distance bound() const { return bound_; }
  // Promises that `count` eligible places lie at or below b: farther ones are skipped from the
  // start. A wrong promise shows as size() < count at the end.
  void tighten(Distance b) { bound_ = std::min(bound_, b); }
  std::size_t size() const { return std::min(items_.size(), count_); }
  bool full() const { return items_.size() >= count_; }
  const std::function<bool(std::size_t)>& eligible() const { return *eligible_; }
  void add(Distance dist, std::size_t index) {
    if (dist > bound_ || !(*eligible_)(index)) return;
    items_.emplace_back(dist, index);
    if (items_.size() == count_) {
      bound_ = std::max_element(items_.begin(), items_.end())->first;
    } else if (items_.size() >= 2 * count_) {
      cut();
    }
  }
  // The nearest, nearest first.
  void finish(Items& out) {
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
  Distance bound_ = std::numeric_limits<Distance>::max();
  const std::function<bool(std::size_t)>* eligible_;
  Items items_;
};

}  // namespace loopscan
