#include "loopscan/core/database/key_scan.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>

#include "loopscan/core/simd.hpp"

#if LOOPSCAN_HAVE_AVX2_CLONES
#include <immintrin.h>
#endif

namespace loopscan {
namespace {

constexpr int B = KeyScan::kBlock;

// The `count` nearest eligible places of one query key: candidates closer than the bound are
// appended and the buffer is cut back to the `count` best whenever it holds 2 count (amortised
// O(1) a place; a heap costs O(log count) each).
class Nearest {
 public:
  Nearest(std::size_t count, const std::function<bool(std::size_t)>& eligible)
      : count_(count), eligible_(&eligible) {
    items_.reserve(2 * count + 1);
  }
  float bound() const { return bound_; }
  void add(float dist, std::size_t index) {
    if (dist > bound_ || !(*eligible_)(index)) return;
    items_.emplace_back(dist, index);
    if (items_.size() == count_) {
      bound_ = std::max_element(items_.begin(), items_.end())->first;
    } else if (items_.size() >= 2 * count_) {
      cut();
    }
  }
  void finish(std::vector<std::pair<float, std::size_t>>& out) {
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
  float bound_ = std::numeric_limits<float>::max();
  const std::function<bool(std::size_t)>* eligible_;
  std::vector<std::pair<float, std::size_t>> items_;
};

// The distances of one block's 16 places to query key q, lane by lane as distance() does.
void block_distances_base(const float* block, const float* q, int dims, float* out) {
  for (int l = 0; l < B; ++l) out[l] = 0.f;
  for (int d = 0; d < dims; ++d) {
    for (int l = 0; l < B; ++l) {
      const float e = block[d * B + l] - q[d];
      out[l] += e * e;
    }
  }
}

void scan_base(const float* blocks, std::size_t n_blocks, int dims, const float* queries,
               int n_queries, std::vector<Nearest>& sinks) {
  float dist[B];
  for (std::size_t b = 0; b < n_blocks; ++b) {
    const float* block = blocks + b * dims * B;
    for (int v = 0; v < n_queries; ++v) {
      block_distances_base(block, queries + v * dims, dims, dist);
      for (int l = 0; l < B; ++l) {
        if (dist[l] <= sinks[v].bound()) sinks[v].add(dist[l], b * B + l);
      }
    }
  }
}

#if LOOPSCAN_HAVE_AVX2_CLONES
LOOPSCAN_AVX2 void scan_avx2(const float* blocks, std::size_t n_blocks, int dims,
                             const float* queries, int n_queries, std::vector<Nearest>& sinks) {
  alignas(32) float dist[B];
  for (std::size_t b = 0; b < n_blocks; ++b) {
    const float* block = blocks + b * dims * B;
    for (int v = 0; v < n_queries; ++v) {
      const float* q = queries + v * dims;
      __m256 lo = _mm256_setzero_ps(), hi = _mm256_setzero_ps();
      for (int d = 0; d < dims; ++d) {
        const __m256 qd = _mm256_set1_ps(q[d]);
        const __m256 e0 = _mm256_sub_ps(_mm256_loadu_ps(block + d * B), qd);
        const __m256 e1 = _mm256_sub_ps(_mm256_loadu_ps(block + d * B + 8), qd);
        lo = _mm256_add_ps(lo, _mm256_mul_ps(e0, e0));
        hi = _mm256_add_ps(hi, _mm256_mul_ps(e1, e1));
      }
      const __m256 bound = _mm256_set1_ps(sinks[v].bound());
      unsigned mask =
          static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(lo, bound, _CMP_LE_OQ)) |
                                _mm256_movemask_ps(_mm256_cmp_ps(hi, bound, _CMP_LE_OQ)) << 8);
      if (!mask) continue;
      _mm256_store_ps(dist, lo);
      _mm256_store_ps(dist + 8, hi);
      for (; mask; mask &= mask - 1) {
        const int l = __builtin_ctz(mask);
        sinks[v].add(dist[l], b * B + l);
      }
    }
  }
}

LOOPSCAN_AVX512 void scan_avx512(const float* blocks, std::size_t n_blocks, int dims,
                                 const float* queries, int n_queries, std::vector<Nearest>& sinks) {
  alignas(64) float dist[B];
  for (std::size_t b = 0; b < n_blocks; ++b) {
    const float* block = blocks + b * dims * B;
    for (int v = 0; v < n_queries; ++v) {
      const float* q = queries + v * dims;
      __m512 acc = _mm512_setzero_ps();
      for (int d = 0; d < dims; ++d) {
        const __m512 e = _mm512_sub_ps(_mm512_loadu_ps(block + d * B), _mm512_set1_ps(q[d]));
        acc = _mm512_add_ps(acc, _mm512_mul_ps(e, e));
      }
      unsigned mask = _mm512_cmp_ps_mask(acc, _mm512_set1_ps(sinks[v].bound()), _CMP_LE_OQ);
      if (!mask) continue;
      _mm512_store_ps(dist, acc);
      for (; mask; mask &= mask - 1) {
        const int l = __builtin_ctz(mask);
        sinks[v].add(dist[l], b * B + l);
      }
    }
  }
}
#endif

}  // namespace

KeyScan::KeyScan(int dims) : dims_(dims) {}

void KeyScan::add(const float* key) {
  const std::size_t lane = count_ % B;
  if (lane == 0) {
    blocks_.resize(blocks_.size() + static_cast<std::size_t>(dims_) * B,
                   std::numeric_limits<float>::infinity());
  }
  float* block = blocks_.data() + blocks_.size() - static_cast<std::size_t>(dims_) * B;
  for (int d = 0; d < dims_; ++d) block[d * B + lane] = key[d];
  ++count_;
}

float KeyScan::distance(const float* a, const float* b, int dims) {
  float s = 0.f;
  for (int d = 0; d < dims; ++d) {
    const float e = a[d] - b[d];
    s += e * e;
  }
  return s;
}

void KeyScan::nearest(const float* queries, int n_queries, std::size_t count,
                      const std::function<bool(std::size_t)>& eligible,
                      std::vector<std::vector<std::pair<float, std::size_t>>>& out) const {
  out.resize(static_cast<std::size_t>(std::max(0, n_queries)));
  for (auto& o : out) o.clear();
  if (count == 0 || count_ == 0 || n_queries <= 0) return;
  std::vector<Nearest> sinks;
  sinks.reserve(static_cast<std::size_t>(n_queries));
  for (int v = 0; v < n_queries; ++v) sinks.emplace_back(count, eligible);
  const std::size_t n_blocks = (count_ + B - 1) / B;
#if LOOPSCAN_HAVE_AVX2_CLONES
  if (simd::has_avx512()) {
    scan_avx512(blocks_.data(), n_blocks, dims_, queries, n_queries, sinks);
  } else if (simd::has_avx2()) {
    scan_avx2(blocks_.data(), n_blocks, dims_, queries, n_queries, sinks);
  } else
#endif
  {
    scan_base(blocks_.data(), n_blocks, dims_, queries, n_queries, sinks);
  }
  for (int v = 0; v < n_queries; ++v) sinks[v].finish(out[v]);
}

}  // namespace loopscan
