#include "loopscan/core/database/key_index.hpp"

#include <algorithm>
#include <initializer_list>
#include <limits>

#include <nanoflann.hpp>

#include "loopscan/core/database/nearest_set.hpp"

namespace loopscan {
namespace {

// The keys of one tree's places as nanoflann sees them: while the tree is built, a gathered
// array; once built, the keys in the tree's leaf order (`leaf`, with `ids` giving each one's
// place), so a search reads each leaf's keys contiguously instead of one scattered key per
// point (at 10^6 places the scattered reads dominated).
struct KeyRange {
  const float* data = nullptr;
  int dims = 0;
  std::size_t size = 0;
  std::vector<float> leaf;
  std::vector<std::uint32_t> ids;
  std::size_t kdtree_get_point_count() const { return size; }
  float kdtree_get_pt(std::uint32_t i, std::size_t d) const { return data[i * dims + d]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<float, KeyRange, float, std::uint32_t>, KeyRange, -1,
    std::uint32_t>;

// nanoflann's result-set interface over a NearestSet that skips places the query may not
// match, so the tree's pruning bound is (at most a little above) the k-th *eligible* distance
// and the answer is exact among eligible places.
class EligibleKnn {
 public:
  using DistanceType = float;
  using IndexType = std::uint32_t;
  EligibleKnn(std::size_t capacity, const std::function<bool(std::size_t)>& eligible)
      : set_(capacity, eligible) {}
  std::size_t size() const { return set_.size(); }
  bool full() const { return set_.full(); }
  float worstDist() const { return set_.bound(); }
  // Tree searches report positions in their leaf order: `ids` turns them into places.
  void set_ids(const std::uint32_t* ids) { ids_ = ids; }
  bool addPoint(float dist, std::uint32_t local) {
    set_.add(dist, ids_ ? ids_[local] : local);
    return true;
  }
  void finish(std::vector<std::pair<float, std::size_t>>& out) { set_.finish(out); }

 private:
  NearestSet<float> set_;
  const std::uint32_t* ids_ = nullptr;
};

// Searches asking for more than 1/kScanShare of the places scan instead of using the tree.
constexpr std::size_t kScanShare = 32;

}  // namespace

// Two static trees and a short tail searched by brute force: the main tree over the first
// places, a second tree over the places added since, rebuilt whenever the tail reaches
// kTail places, and merged into the main tree when it reaches half the main tree's size.
// Adding stays amortised O(log n) a place, and a query never scans more than kTail keys.
// Static trees search several times faster than nanoflann's dynamic forest of log2(n) trees.
constexpr std::size_t kTail = 1024;

struct KeyIndex::Impl {
  int dims;
  std::size_t count = 0;
  KeyRange main_range, second_range;  // each holds its places' keys, in leaf order
  std::unique_ptr<Tree> main, second;
  std::vector<float> tail;  // keys of the places [tail_first, count), not in a tree yet
  std::size_t tail_first = 0;
  explicit Impl(int d) : dims(d) {}

  // A tree over the keys of `parts` (and the tail): gathered, indexed, then re-laid in the
  // tree's order with the permutation made the identity. Frees the parts' copies.
  std::unique_ptr<Tree> build(KeyRange& range, std::initializer_list<KeyRange*> parts) {
    std::vector<float> keys;
    std::vector<std::uint32_t> ids;
    for (KeyRange* part : parts) {
      keys.insert(keys.end(), part->leaf.begin(), part->leaf.end());
      ids.insert(ids.end(), part->ids.begin(), part->ids.end());
      *part = KeyRange{};
    }
    keys.insert(keys.end(), tail.begin(), tail.end());
    for (std::size_t i = tail_first; i < count; ++i) ids.push_back(static_cast<std::uint32_t>(i));
    range = KeyRange{keys.data(), dims, ids.size(), {}, {}};
    auto tree = std::make_unique<Tree>(dims, range, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    tree->buildIndex();
    range.leaf.resize(keys.size());
    range.ids.resize(ids.size());
    for (std::size_t j = 0; j < ids.size(); ++j) {
      const std::size_t i = tree->vAcc[j];
      std::copy_n(&keys[i * dims], dims, &range.leaf[j * dims]);
      range.ids[j] = ids[i];
      tree->vAcc[j] = static_cast<std::uint32_t>(j);
    }
    range.data = range.leaf.data();
    tail.clear();
    tail.shrink_to_fit();
    tail_first = count;
    return tree;
  }
  void added() {
    if (count - tail_first < kTail) return;
    if (count - main_range.size > std::max(kTail, main_range.size / 2)) {
      main = build(main_range, {&main_range, &second_range});
      second.reset();
    } else {
      second = build(second_range, {&second_range});
    }
  }
  // Every place's key with its id, in storage order (the brute-force path).
  template <class F>
  void for_each_key(F&& f) const {
    for (const KeyRange* r : {&main_range, &second_range}) {
      for (std::size_t j = 0; j < r->ids.size(); ++j) f(&r->leaf[j * dims], r->ids[j]);
    }
    for (std::size_t i = tail_first; i < count; ++i) {
      f(&tail[(i - tail_first) * dims], static_cast<std::uint32_t>(i));
    }
  }
};

KeyIndex::KeyIndex(int dims) : impl_(std::make_unique<Impl>(dims)) {}
KeyIndex::~KeyIndex() = default;

void KeyIndex::add(const float* key) {
  Impl& k = *impl_;
  k.tail.insert(k.tail.end(), key, key + k.dims);
  ++k.count;
  k.added();
}

std::size_t KeyIndex::size() const { return impl_->count; }
int KeyIndex::dims() const { return impl_->dims; }

void KeyIndex::nearest(const float* key, std::size_t count,
                       const std::function<bool(std::size_t)>& eligible,
                       std::vector<std::pair<float, std::size_t>>& out) const {
  out.clear();
  const Impl& k = *impl_;
  if (count == 0 || k.count == 0) return;
  auto dist = [&](const float* x) {
    float d = 0;
    for (int t = 0; t < k.dims; ++t) {
      const float e = key[t] - x[t];
      d += e * e;
    }
    return d;
  };
  // A large share of the places (pool searches) prunes little in a tree: one pass over the
  // keys and a selection is faster there, and gives the same answer.
  if (count * kScanShare >= k.count) {
    // Distances first (no calls in the loop), then the result set, which asks `eligible` only
    // for places closer than its bound.
    std::vector<std::pair<float, std::uint32_t>> d;
    d.reserve(k.count);
    k.for_each_key([&](const float* x, std::uint32_t id) { d.emplace_back(dist(x), id); });
    EligibleKnn best(count, eligible);
    for (const auto& [di, id] : d) best.addPoint(di, id);
    best.finish(out);
    return;
  }
  EligibleKnn result(count, eligible);
  result.set_ids(k.main_range.ids.data());
  if (k.main) k.main->findNeighbors(result, key, nanoflann::SearchParams());
  result.set_ids(k.second_range.ids.data());
  if (k.second) k.second->findNeighbors(result, key, nanoflann::SearchParams());
  result.set_ids(nullptr);
  for (std::size_t i = k.tail_first; i < k.count; ++i) {
    result.addPoint(dist(&k.tail[(i - k.tail_first) * k.dims]), static_cast<std::uint32_t>(i));
  }
  result.finish(out);
}

std::size_t KeyIndex::memory_bytes() const {
  // The keys (in the trees, in leaf order, with their place ids; the tail), the trees'
  // permutations (uint32 a place) and about one node per leaf of 16 points.
  const Impl& k = *impl_;
  std::size_t bytes = k.tail.capacity() * sizeof(float);
  for (const KeyRange* r : {&k.main_range, &k.second_range}) {
    bytes += r->leaf.capacity() * sizeof(float) + r->ids.capacity() * 2 * sizeof(std::uint32_t);
  }
  return bytes + (k.count / 8 + 1) * 64;
}

}  // namespace loopscan
