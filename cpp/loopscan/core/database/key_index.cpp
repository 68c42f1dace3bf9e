#include "loopscan/core/database/key_index.hpp"

#include <algorithm>
#include <limits>

#include <nanoflann.hpp>

namespace loopscan {
namespace {

struct PayloadKeys {
  int dims = 0;
  std::vector<float> keys;     // dims per place
  std::size_t count = 0;       // places added
  std::size_t tree_count = 0;  // places in the tree (the first ones)
  std::size_t kdtree_get_point_count() const { return tree_count; }
  float kdtree_get_pt(std::uint32_t i, std::size_t d) const { return keys[i * dims + d]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<
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
    return full() ? items_.front().first : std::numeric_limits<float>::max();
  }
  bool addPoint(float dist, std::uint32_t index) {
    if (full() && dist >= items_.front().first) return true;
    if (!eligible_(index)) return true;
    items_.emplace_back(dist, index);  // max-heap on distance: the worst kept is in front
    std::push_heap(items_.begin(), items_.end());
    if (items_.size() > capacity_) {
      std::pop_heap(items_.begin(), items_.end());
      items_.pop_back();
    }
    return true;
  }
  std::vector<std::pair<float, std::size_t>>& sorted_items() {
    std::sort_heap(items_.begin(), items_.end());
    return items_;
  }

 private:
  std::size_t capacity_;
  const std::function<bool(std::size_t)>& eligible_;
  std::vector<std::pair<float, std::size_t>> items_;
};

// Searches asking for more than 1/kScanShare of the places scan instead of using the tree.
constexpr std::size_t kScanShare = 32;

}  // namespace

// One static tree over the first places plus a short tail searched by brute force; the tree
// is rebuilt when the tail reaches half its size (amortised O(log n) per added place). A
// single tree searches several times faster than nanoflann's dynamic forest of log2(n) trees.
struct KeyIndex::Impl {
  PayloadKeys keys;
  std::unique_ptr<Tree> tree;
  explicit Impl(int dims) : keys{dims, {}, 0, 0} {}
  void rebuild() {
    keys.tree_count = keys.count;
    tree = std::make_unique<Tree>(keys.dims, keys, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    tree->buildIndex();
  }
};

KeyIndex::KeyIndex(int dims) : impl_(std::make_unique<Impl>(dims)) {}
KeyIndex::~KeyIndex() = default;

void KeyIndex::add(const float* key) {
  PayloadKeys& k = impl_->keys;
  k.keys.insert(k.keys.end(), key, key + k.dims);
  ++k.count;
  if (k.count - k.tree_count > std::max<std::size_t>(64, k.tree_count / 2)) impl_->rebuild();
}

std::size_t KeyIndex::size() const { return impl_->keys.count; }
int KeyIndex::dims() const { return impl_->keys.dims; }

void KeyIndex::nearest(const float* key, std::size_t count,
                       const std::function<bool(std::size_t)>& eligible,
                       std::vector<std::pair<float, std::size_t>>& out) const {
  out.clear();
  if (count == 0 || impl_->keys.count == 0) return;
  const PayloadKeys& k = impl_->keys;
  auto dist = [&](std::size_t i) {
    float d = 0;
    for (int t = 0; t < k.dims; ++t) {
      const float e = key[t] - k.keys[i * k.dims + t];
      d += e * e;
    }
    return d;
  };
  // A large share of the places (pool searches) prunes little in a tree: one pass over the
  // contiguous keys and a selection is faster there, and gives the same answer.
  if (count * kScanShare >= k.count) {
    // Distances first (no calls in the loop), then a bounded max-heap that asks `eligible`
    // only for places closer than the current k-th.
    std::vector<float> d(k.count);
    for (std::size_t i = 0; i < k.count; ++i) d[i] = dist(i);
    EligibleKnn best(count, eligible);
    for (std::size_t i = 0; i < k.count; ++i) best.addPoint(d[i], static_cast<std::uint32_t>(i));
    out.swap(best.sorted_items());
    return;
  }
  EligibleKnn result(count, eligible);
  if (impl_->tree) impl_->tree->findNeighbors(result, key, nanoflann::SearchParams());
  for (std::size_t i = k.tree_count; i < k.count; ++i) {
    result.addPoint(dist(i), static_cast<std::uint32_t>(i));
  }
  out.swap(result.sorted_items());
}

std::size_t KeyIndex::memory_bytes() const {
  // The keys and a point id (uint32) per place, plus about one node per leaf of 16 points.
  const std::size_t n = impl_->keys.count;
  return impl_->keys.keys.capacity() * sizeof(float) + n * sizeof(std::uint32_t) + (n / 8 + 1) * 64;
}

}  // namespace loopscan
