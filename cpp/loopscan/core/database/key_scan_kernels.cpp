#include "loopscan/core/database/key_scan_kernels.hpp"

#include <cmath>

#include "loopscan/core/database/nearest_set.hpp"
#include "loopscan/core/simd.hpp"

#if LOOPSCAN_HAVE_AVX2_CLONES
#include <immintrin.h>
#define LOOPSCAN_AVX512BW __attribute__((target("avx2,fma,avx512f,avx512dq,avx512vl,avx512bw")))
#endif

namespace loopscan::key_scan {
namespace {

constexpr int kCheck = 4;  // dimension pairs summed between two checks against the bound

// Hands the lanes in `mask` to the sink.
LOOPSCAN_INLINE void emit(unsigned mask, const std::uint32_t* dist, const std::uint32_t* ids,
                          Nearest& sink) {
  for (; mask; mask &= mask - 1) {
    const int l = __builtin_ctz(mask);
    sink.add(dist[l], ids[l]);
  }
}

void scan_base(const BlockRef* blocks, std::size_t n_blocks, int pairs,
               const std::uint32_t* queries, int n_queries, Nearest* sinks) {
  std::uint32_t dist[kBlock];
  for (std::size_t b = 0; b < n_blocks; ++b) {
    const std::uint16_t* keys = blocks[b].keys;
    for (int v = 0; v < n_queries; ++v) {
      const std::uint32_t* q = queries + static_cast<std::size_t>(v) * pairs;
      unsigned mask = 0;
      for (int l = 0; l < kBlock; ++l) {
        std::uint32_t s = 0;
        for (int p = 0; p < pairs; ++p) {
          const int e0 = int(keys[(p * kBlock + l) * 2]) - int(q[p] & 0xffffu);
          const int e1 = int(keys[(p * kBlock + l) * 2 + 1]) - int(q[p] >> 16);
          s += static_cast<std::uint32_t>(e0 * e0 + e1 * e1);
        }
        dist[l] = s;
        if (s <= sinks[v].bound()) mask |= 1u << l;
      }
      emit(mask & blocks[b].valid, dist, blocks[b].ids, sinks[v]);
    }
  }
}

#if LOOPSCAN_HAVE_AVX2_CLONES
// acc <= bound as unsigned 32-bit lanes, as a mask of 8 bits.
LOOPSCAN_AVX2 inline unsigned at_most(__m256i acc, __m256i bound) {
  const __m256i le = _mm256_cmpeq_epi32(_mm256_max_epu32(acc, bound), bound);
  return static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(le)));
}

LOOPSCAN_AVX2 void scan_avx2(const BlockRef* blocks, std::size_t n_blocks, int pairs,
                             const std::uint32_t* queries, int n_queries, Nearest* sinks) {
  alignas(32) std::uint32_t dist[kBlock];
  for (std::size_t b = 0; b < n_blocks; ++b) {
    const std::uint16_t* keys = blocks[b].keys;
    for (int v = 0; v < n_queries; ++v) {
      const std::uint32_t* q = queries + static_cast<std::size_t>(v) * pairs;
      const __m256i bound = _mm256_set1_epi32(static_cast<int>(sinks[v].bound()));
      __m256i lo = _mm256_setzero_si256(), hi = _mm256_setzero_si256();
      unsigned mask = 0;
      for (int p = 0; p < pairs; ++p) {
        const __m256i qp = _mm256_set1_epi32(static_cast<int>(q[p]));
        const auto* row = reinterpret_cast<const __m256i*>(keys + p * kBlock * 2);
        const __m256i e0 = _mm256_sub_epi16(_mm256_loadu_si256(row), qp);
        const __m256i e1 = _mm256_sub_epi16(_mm256_loadu_si256(row + 1), qp);
        lo = _mm256_add_epi32(lo, _mm256_madd_epi16(e0, e0));
        hi = _mm256_add_epi32(hi, _mm256_madd_epi16(e1, e1));
        if (p % kCheck == kCheck - 1 || p == pairs - 1) {
          mask = blocks[b].valid & (at_most(lo, bound) | at_most(hi, bound) << 8);
          if (!mask) break;
        }
      }
      if (!mask) continue;
      _mm256_store_si256(reinterpret_cast<__m256i*>(dist), lo);
      _mm256_store_si256(reinterpret_cast<__m256i*>(dist + 8), hi);
      emit(mask, dist, blocks[b].ids, sinks[v]);
    }
  }
}

LOOPSCAN_AVX512BW void scan_avx512(const BlockRef* blocks, std::size_t n_blocks, int pairs,
                                   const std::uint32_t* queries, int n_queries, Nearest* sinks) {
  alignas(64) std::uint32_t dist[kBlock];
  for (std::size_t b = 0; b < n_blocks; ++b) {
    const std::uint16_t* keys = blocks[b].keys;
    if (b + 1 < n_blocks) __builtin_prefetch(blocks[b + 1].keys);
    for (int v = 0; v < n_queries; ++v) {
      const std::uint32_t* q = queries + static_cast<std::size_t>(v) * pairs;
      const __m512i bound = _mm512_set1_epi32(static_cast<int>(sinks[v].bound()));
      __m512i acc = _mm512_setzero_si512();
      unsigned mask = 0;
      for (int p = 0; p < pairs; ++p) {
        const __m512i e = _mm512_sub_epi16(_mm512_loadu_si512(keys + p * kBlock * 2),
                                           _mm512_set1_epi32(static_cast<int>(q[p])));
        acc = _mm512_add_epi32(acc, _mm512_madd_epi16(e, e));
        if (p % kCheck == kCheck - 1 || p == pairs - 1) {
          mask = blocks[b].valid & _mm512_cmple_epu32_mask(acc, bound);
          if (!mask) break;
        }
      }
      if (!mask) continue;
      _mm512_store_si512(dist, acc);
      emit(mask, dist, blocks[b].ids, sinks[v]);
    }
  }
}

LOOPSCAN_AVX2 void scan_float_avx2(const FloatBlockRef* blocks, std::size_t n_blocks, int dims,
                                   const float* query, float* out) {
  for (std::size_t b = 0; b < n_blocks; ++b) {
    __m256 lo = _mm256_setzero_ps(), hi = _mm256_setzero_ps();
    for (int d = 0; d < dims; ++d) {
      const __m256 qd = _mm256_set1_ps(query[d]);
      const __m256 e0 = _mm256_sub_ps(_mm256_loadu_ps(blocks[b].keys + d * kBlock), qd);
      const __m256 e1 = _mm256_sub_ps(_mm256_loadu_ps(blocks[b].keys + d * kBlock + 8), qd);
      lo = _mm256_fmadd_ps(e0, e0, lo);
      hi = _mm256_fmadd_ps(e1, e1, hi);
    }
    _mm256_storeu_ps(out + b * kBlock, lo);
    _mm256_storeu_ps(out + b * kBlock + 8, hi);
  }
}
#endif

void scan_float_base(const FloatBlockRef* blocks, std::size_t n_blocks, int dims,
                     const float* query, float* out) {
  for (std::size_t b = 0; b < n_blocks; ++b) {
    for (int l = 0; l < kBlock; ++l) {
      float s = 0.f;
      for (int d = 0; d < dims; ++d) {
        const float e = blocks[b].keys[d * kBlock + l] - query[d];
        s = std::fma(e, e, s);
      }
      out[b * kBlock + l] = s;
    }
  }
}

bool has_avx512bw() {
#if LOOPSCAN_HAVE_AVX2_CLONES
  static const bool yes = simd::has_avx512() && __builtin_cpu_supports("avx512bw");
  return yes;
#else
  return false;
#endif
}

}  // namespace

void scan(const BlockRef* blocks, std::size_t n_blocks, int pairs, const std::uint32_t* queries,
          int n_queries, Nearest* sinks) {
#if LOOPSCAN_HAVE_AVX2_CLONES
  if (has_avx512bw()) return scan_avx512(blocks, n_blocks, pairs, queries, n_queries, sinks);
  if (simd::has_avx2()) return scan_avx2(blocks, n_blocks, pairs, queries, n_queries, sinks);
#endif
  scan_base(blocks, n_blocks, pairs, queries, n_queries, sinks);
}

void scan_float(const FloatBlockRef* blocks, std::size_t n_blocks, int dims, const float* query,
                float* out) {
#if LOOPSCAN_HAVE_AVX2_CLONES
  if (simd::has_avx2()) return scan_float_avx2(blocks, n_blocks, dims, query, out);
#endif
  scan_float_base(blocks, n_blocks, dims, query, out);
}

}  // namespace loopscan::key_scan
