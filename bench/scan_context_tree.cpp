#include "scan_context_tree.hpp"

#include <cmath>
#include <limits>

#include <nanoflann.hpp>

namespace loopscan::bench {
namespace {

struct RingKeys {
  const std::vector<float>* keys;
  int dims;
  std::size_t count;
  std::size_t kdtree_get_point_count() const { return count; }
  float kdtree_get_pt(std::uint32_t i, std::size_t d) const { return (*keys)[i * dims + d]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using KdTree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<float, RingKeys, float, std::uint32_t>, RingKeys, -1,
    std::uint32_t>;

// Per ring and per sector means of a structure half laid out sector x ring.
void keys_of(const float* cells, int R, int S, float* ring_key, float* sector_key) {
  for (int r = 0; r < R; ++r) ring_key[r] = 0;
  for (int s = 0; s < S; ++s) {
    float sum = 0;
    for (int r = 0; r < R; ++r) {
      ring_key[r] += cells[s * R + r] / S;
      sum += cells[s * R + r];
    }
    sector_key[s] = sum / R;
  }
}

}  // namespace

struct ScanContextTree::Tree {
  RingKeys data;
  KdTree tree;
  Tree(const std::vector<float>& keys, int dims, std::size_t count)
      : data{&keys, dims, count}, tree(dims, data, nanoflann::KDTreeSingleIndexAdaptorParams(10)) {
    tree.buildIndex();
  }
};

ScanContextTree::ScanContextTree(int rings, int sectors) : rings_(rings), sectors_(sectors) {}
ScanContextTree::~ScanContextTree() = default;

void ScanContextTree::add(const Signature& signature) {
  const int R = rings_, S = sectors_;
  const std::size_t at = cells_.size();
  cells_.resize(at + static_cast<std::size_t>(R) * S);
  for (int i = 0; i < R * S; ++i) cells_[at + i] = static_cast<float>(signature(0, i));
  ring_keys_.resize(ring_keys_.size() + R);
  sector_keys_.resize(sector_keys_.size() + S);
  keys_of(&cells_[at], R, S, &ring_keys_[count_ * R], &sector_keys_[count_ * S]);
  ++count_;
}

void ScanContextTree::build() { tree_ = std::make_unique<Tree>(ring_keys_, rings_, count_); }

double ScanContextTree::distance(const float* q, const float* q_sector_key,
                                 std::size_t place) const {
  const int R = rings_, S = sectors_, radius = static_cast<int>(std::lround(0.5 * 0.1 * S));
  const float* p = &cells_[place * R * S];
  const float* pk = &sector_keys_[place * S];
  // The shift whose sector keys differ least, then the best column-cosine distance around it.
  int key_shift = 0;
  float least = std::numeric_limits<float>::max();
  for (int shift = 0; shift < S; ++shift) {
    float d = 0;
    for (int s = 0; s < S; ++s) d += std::abs(q_sector_key[s] - pk[(s + shift) % S]);
    if (d < least) least = d, key_shift = shift;
  }
  double best = std::numeric_limits<double>::max();
  for (int t = -radius; t <= radius; ++t) {
    const int shift = ((key_shift + t) % S + S) % S;
    double sum = 0;
    int columns = 0;
    for (int s = 0; s < S; ++s) {
      const float* a = q + s * R;
      const float* b = p + ((s + shift) % S) * R;
      float ab = 0, aa = 0, bb = 0;
      for (int r = 0; r < R; ++r) ab += a[r] * b[r], aa += a[r] * a[r], bb += b[r] * b[r];
      if (aa == 0 || bb == 0) continue;
      sum += ab / std::sqrt(double(aa) * bb);
      ++columns;
    }
    best = std::min(best, columns > 0 ? 1.0 - sum / columns : 1.0);
  }
  return best;
}

std::pair<std::size_t, double> ScanContextTree::query(const Signature& signature,
                                                      int candidates) const {
  const int R = rings_, S = sectors_;
  std::vector<float> q(static_cast<std::size_t>(R) * S), ring_key(R), sector_key(S);
  for (int i = 0; i < R * S; ++i) q[i] = static_cast<float>(signature(0, i));
  keys_of(q.data(), R, S, ring_key.data(), sector_key.data());
  std::vector<std::uint32_t> ids(candidates);
  std::vector<float> d2(candidates);
  const std::size_t found =
      tree_->tree.knnSearch(ring_key.data(), candidates, ids.data(), d2.data());
  std::pair<std::size_t, double> best{0, std::numeric_limits<double>::max()};
  for (std::size_t j = 0; j < found; ++j) {
    const double d = distance(q.data(), sector_key.data(), ids[j]);
    if (d < best.second) best = {ids[j], d};
  }
  return best;
}

std::pair<std::size_t, double> ScanContextTree::brute_force(const Signature& signature) const {
  const int R = rings_, S = sectors_;
  std::vector<float> q(static_cast<std::size_t>(R) * S), ring_key(R), sector_key(S);
  for (int i = 0; i < R * S; ++i) q[i] = static_cast<float>(signature(0, i));
  keys_of(q.data(), R, S, ring_key.data(), sector_key.data());
  std::pair<std::size_t, double> best{0, std::numeric_limits<double>::max()};
  for (std::size_t i = 0; i < count_; ++i) {
    const double d = distance(q.data(), sector_key.data(), i);
    if (d < best.second) best = {i, d};
  }
  return best;
}

std::size_t ScanContextTree::memory_bytes() const {
  return (cells_.capacity() + ring_keys_.capacity() + sector_keys_.capacity()) * sizeof(float) +
         count_ * sizeof(std::uint32_t) + (count_ / 5 + 1) * 64;
}

}  // namespace loopscan::bench
