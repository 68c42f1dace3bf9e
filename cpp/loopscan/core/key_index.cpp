#include "loopscan/core/key_index.hpp"

#include <algorithm>
#include <limits>

#include <nanoflann.hpp>

namespace loopscan {
namespace {

struct PayloadKeys {
  KeyLayout layout;
  const PayloadArena* data = nullptr;
  std::size_t count = 0;
  std::size_t kdtree_get_point_count() const { return count; }
  float kdtree_get_pt(std::uint32_t i, std::size_t d) const {
    return data->at(i)[layout.offset + d * layout.step];
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using Tree = nanoflann::KDTreeSingleIndexDynamicAdaptor<
    nanoflann::L2_Simple_Adaptor<float, PayloadKeys, float, std::uint32_t>, PayloadKeys, -1,
    std::uint32_t>;

// k-nearest result set that skips places the query may not match, so the tree's pruning
// bound is the k-th *eligible* distance and the answer is exact among eligible places.
class EligibleKnn {
 public:
  using DistanceType = float;
  using IndexType = std::uint32_t;
  EligibleKnn(std::size_t capacity, const std::function<bool(std::size_t)>& eligible)
      : capacity_(capacity), eligible_(eligible) {
    items_.reserve(capacity + 1);
  }
  std::size_t size() const { return items_.size(); }
  bool full() const { return items_.size() == capacity_; }
  float worstDist() const {
    return full() ? items_.back().first : std::numeric_limits<float>::max();
  }
  bool addPoint(float dist, std::uint32_t index) {
    if (full() && dist >= items_.back().first) return true;
    if (!eligible_(index)) return true;
    const std::pair<float, std::size_t> item{dist, index};
    items_.insert(std::upper_bound(items_.begin(), items_.end(), item), item);
    if (items_.size() > capacity_) items_.pop_back();
    return true;
  }
  std::vector<std::pair<float, std::size_t>>& items() { return items_; }

 private:
  std::size_t capacity_;
  const std::function<bool(std::size_t)>& eligible_;
  std::vector<std::pair<float, std::size_t>> items_;
};

}  // namespace

struct KeyIndex::Impl {
  PayloadKeys keys;
  Tree tree;
  Impl(const KeyLayout& layout, const PayloadArena* data)
      : keys{layout, data, 0},
        tree(layout.dims, keys, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {}
};

KeyIndex::KeyIndex(const KeyLayout& layout, const PayloadArena* data)
    : impl_(std::make_unique<Impl>(layout, data)) {}
KeyIndex::~KeyIndex() = default;

void KeyIndex::extend(std::size_t n) {
  const std::size_t start = impl_->keys.count;
  if (n <= start) return;
  impl_->keys.count = n;
  impl_->tree.addPoints(static_cast<std::uint32_t>(start), static_cast<std::uint32_t>(n - 1));
}

std::size_t KeyIndex::indexed() const { return impl_->keys.count; }

void KeyIndex::nearest(const float* key, std::size_t count,
                       const std::function<bool(std::size_t)>& eligible,
                       std::vector<std::pair<float, std::size_t>>& out) const {
  out.clear();
  if (count == 0 || impl_->keys.count == 0) return;
  EligibleKnn result(count, eligible);
  impl_->tree.findNeighbors(result, key, nanoflann::SearchParams());
  out.swap(result.items());
}

std::size_t KeyIndex::memory_bytes() const {
  // Point ids (uint32) and tree membership (int) per place, plus about one node per leaf of
  // 16 points in the forest.
  const std::size_t n = impl_->keys.count;
  return n * (sizeof(std::uint32_t) + sizeof(int)) + (n / 8 + 1) * 64;
}

}  // namespace loopscan
