// Pair kernel: (1) element-wise products of the packed query (and its ring-swapped copy) with
// the place, summed over the rings, give the ring-summed correlation and convolution spectra;
// (2) an inverse real DFT evaluated for shifts m, S - m, S/2 - m and S/2 + m at once gives the
// best dot. The default 60 sectors get a vectorised instantiation; other sizes a scalar path.
#include "loopscan/core/matching/scan_context_pair_kernel.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "loopscan/core/simd.hpp"

namespace loopscan {
namespace {

constexpr int kMaxSectors = kMaxSpectraSectors;
constexpr int kFastSectors = 60;

// Scalar ring sums: a[j] = sum_r q[r S + j] p[r S + j].
void ring_sums_scalar(const float* q, const float* p, int rings, int S, float* a) {
  std::fill(a, a + S, 0.f);
  for (int r = 0; r < rings; ++r) {
    for (int j = 0; j < S; ++j) a[j] += q[r * S + j] * p[r * S + j];
  }
}

// Both ring sums for S = 60 with vectors: blocks of 240 floats (four rings; 15 vectors of 16,
// 30 of 8 or 60 of 4, so every width sums each lane in the same order); five vectors at a time
// keep 10 accumulators in registers and load each place vector once for the two products.
// The blocks are folded back to S sums at the end.
template <int W>
LOOPSCAN_INLINE void ring_sums_60(const float* q, const float* qs, const float* p, int rings,
                                  float* a1, float* a2) {
  using V = typename simd::Vec<float, W>::type;
  constexpr int kV = simd::Vec<float, W>::kLanes, kBlock = 240, kNV = kBlock / kV, kGroup = 5;
  constexpr int S = kFastSectors, kRingsPerBlock = kBlock / S;
  const int blocks = rings / kRingsPerBlock;
  alignas(32) float buf1[kBlock], buf2[kBlock];
  for (int g = 0; g < kNV; g += kGroup) {
    V x[kGroup], y[kGroup];
    for (int i = 0; i < kGroup; ++i) x[i] = y[i] = V{};
    for (int b = 0; b < blocks; ++b) {
      const std::size_t o = static_cast<std::size_t>(b) * kBlock + g * kV;
      for (int i = 0; i < kGroup; ++i) {
        const V pv = simd::load<V>(p + o + i * kV);
        x[i] += simd::load<V>(q + o + i * kV) * pv;
        y[i] += simd::load<V>(qs + o + i * kV) * pv;
      }
    }
    for (int i = 0; i < kGroup; ++i) {
      simd::store(buf1 + (g + i) * kV, x[i]);
      simd::store(buf2 + (g + i) * kV, y[i]);
    }
  }
  for (int j = 0; j < S; ++j) {
    float s1 = 0, s2 = 0;
    for (int t = 0; t < kRingsPerBlock; ++t) {
      s1 += buf1[t * S + j];
      s2 += buf2[t * S + j];
    }
    a1[j] = s1;
    a2[j] = s2;
  }
  for (int r = blocks * kRingsPerBlock; r < rings; ++r) {
    for (int j = 0; j < S; ++j) {
      a1[j] += q[r * S + j] * p[r * S + j];
      a2[j] += qs[r * S + j] * p[r * S + j];
    }
  }
}

// Correlation (cre, cim) and convolution (vre, vim) spectra from the two ring sums.
LOOPSCAN_INLINE void cross_spectra(const float* a1, const float* a2, int S, float* cre, float* cim,
                                   float* vre, float* vim) {
  const int H = S / 2;
  cre[0] = vre[0] = a1[0];  // DC: Re Q_0 Re P_0
  cre[H] = vre[H] = a1[H];  // Nyquist, packed where Im X_0 would be
  cim[0] = vim[0] = cim[H] = vim[H] = 0.f;
  for (int k = 1; k < H; ++k) {
    const float x = a1[k], y = a1[H + k], z = a2[k], u = a2[H + k];
    cre[k] = x + y;
    cim[k] = z - u;
    vre[k] = x - y;
    vim[k] = z + u;
  }
}

// The best dot over every shift of both spectra (correlation c, convolution v), from m < 16
// only: with A_m = sum_k re_k ic[k][m] and B_m = sum_k im_k is[k][m], shifts m and S - m are
// A + B and A - B; and as ic[k][S/2 - m] = (-1)^k ic[k][m], is[k][S/2 - m] = -(-1)^k is[k][m],
// shifts S/2 -+ m are (A_e - A_o) -+ (B_o - B_e) from the even-k and odd-k sums. Half the
// multiply-adds of the plain product, in another order (the last bits of the dot differ).
// Each lane sums in the same order at any W, so every instantiation gives the same bits.
template <int W>
LOOPSCAN_INLINE float best_of_inverse_sym(const float* cre, const float* cim, const float* vre,
                                          const float* vim, int K, const float* ic, const float* is,
                                          int mp) {
  using V = typename simd::Vec<float, W>::type;
  constexpr int kV = simd::Vec<float, W>::kLanes, kMV = 16 / kV;
  const auto mag = [](V x) { return x < 0 ? -x : x; };
  V best = V{} - 1e30f;
  for (int v = 0; v < kMV; ++v) {
    V ae{}, ao{}, be{}, bo{}, ce{}, co{}, de{}, dd{};
    for (int k = 0; k < K; k += 2) {
      const V icv = simd::load<V>(ic + k * mp + v * kV), isv = simd::load<V>(is + k * mp + v * kV);
      ae += cre[k] * icv;
      be += cim[k] * isv;
      ce += vre[k] * icv;
      de += vim[k] * isv;
      if (k + 1 == K) break;
      const V ic1 = simd::load<V>(ic + (k + 1) * mp + v * kV),
              is1 = simd::load<V>(is + (k + 1) * mp + v * kV);
      ao += cre[k + 1] * ic1;
      bo += cim[k + 1] * is1;
      co += vre[k + 1] * ic1;
      dd += vim[k + 1] * is1;
    }
    const V x1 = (ae + ao) + mag(be + bo), x2 = (ae - ao) + mag(be - bo);
    const V y1 = (ce + co) + mag(de + dd), y2 = (ce - co) + mag(de - dd);
    const V x = x1 > x2 ? x1 : x2, y = y1 > y2 ? y1 : y2;
    best = best > x ? best : x;
    best = best > y ? best : y;
  }
  float m = best[0];
  for (int l = 1; l < kV; ++l) m = m > best[l] ? m : best[l];
  return m;
}

float best_of_inverse_scalar(const float* re, const float* im, int K, const float* ic,
                             const float* is, int M, int mp) {
  float best = -2.f;
  for (int m = 0; m < M; ++m) {
    float a = 0, b = 0;
    for (int k = 0; k < K; ++k) {
      a += re[k] * ic[k * mp + m];
      b += im[k] * is[k * mp + m];
    }
    best = std::max(best, a + std::abs(b));
  }
  return best;
}

using KernelArgs = ScanContextPairArgs;

// W: the vector width; every lane sums in the same order at any W, so the AVX-512 and AVX2
// instantiations give the same bits (the SSE2 one differs by the rounding of unfused FMAs).
template <int W>
LOOPSCAN_INLINE void best_dots_impl(const KernelArgs& k, const float* q, const float* qs,
                                    const float* p, float best[2]) {
  const int S = k.sectors, R = k.rings, H = S / 2, K = H + 1;
  const bool fast = S == kFastSectors;
  float a1[kMaxSectors], a2[kMaxSectors];
  float cre[kMaxSectors / 2 + 1], cim[kMaxSectors / 2 + 1];
  float vre[kMaxSectors / 2 + 1], vim[kMaxSectors / 2 + 1];
  for (int c = 0; c < 2; ++c) {
    const std::size_t off = static_cast<std::size_t>(c) * R * S;
    if (fast) {
      ring_sums_60<W>(q + off, qs + off, p + off, R, a1, a2);
    } else {
      ring_sums_scalar(q + off, p + off, R, S, a1);
      ring_sums_scalar(qs + off, p + off, R, S, a2);
    }
    cross_spectra(a1, a2, S, cre, cim, vre, vim);
    if (fast) {
      best[c] = best_of_inverse_sym<W>(cre, cim, vre, vim, K, k.inv_cos, k.inv_sin, k.m_padded);
    } else {
      best[c] = std::max(best_of_inverse_scalar(cre, cim, K, k.inv_cos, k.inv_sin, K, k.m_padded),
                         best_of_inverse_scalar(vre, vim, K, k.inv_cos, k.inv_sin, K, k.m_padded));
    }
  }
}

void best_dots_base(const KernelArgs& k, const float* q, const float* qs, const float* p,
                    float best[2]) {
  best_dots_impl<16>(k, q, qs, p, best);
}

LOOPSCAN_AVX2 void best_dots_avx2(const KernelArgs& k, const float* q, const float* qs,
                                  const float* p, float best[2]) {
  best_dots_impl<32>(k, q, qs, p, best);
}

LOOPSCAN_AVX512 void best_dots_avx512(const KernelArgs& k, const float* q, const float* qs,
                                      const float* p, float best[2]) {
  best_dots_impl<64>(k, q, qs, p, best);
}

}  // namespace

void scan_context_pair_best_dots(const ScanContextPairArgs& args, const float* q, const float* qs,
                                 const float* p, float best[2]) {
  static const auto kernel = simd::widest(best_dots_avx512, best_dots_avx2, best_dots_base);
  kernel(args, q, qs, p, best);
}

}  // namespace loopscan
