// Packing of Scan Context places into real spectra along the sectors, queries, the pair kernel
// and the double-precision alignment.
#include "loopscan/core/matching/scan_context_spectra.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <vector>

#include "loopscan/core/matching/scaled_accumulate.hpp"
#include "loopscan/core/simd.hpp"

namespace loopscan {
namespace {

constexpr int kMaxSectors = 512;

}  // namespace

ScanContextSpectra::ScanContextSpectra(const ScanContextConfig& config)
    : rings_(config.rings), sectors_(config.sectors) {
  if (rings_ <= 0 || sectors_ <= 0 || sectors_ % 2 != 0 || sectors_ > kMaxSectors) {
    throw std::invalid_argument(
        "Scan Context spectra need rings > 0 and an even number of "
        "sectors up to 512, got " +
        std::to_string(rings_) + " x " + std::to_string(sectors_));
  }
  const int S = sectors_, K = S / 2 + 1;
  m_padded_ = (K + 7) / 8 * 8;
  // Packing is linear in the ring: packed = sum_s x_s * forward_[s] (one S-float row per
  // sector). align() keeps double tables of the inverse.
  forward_.assign(static_cast<std::size_t>(S) * S, 0.f);
  cos_.resize(static_cast<std::size_t>(S) * (S / 2));
  sin_.resize(static_cast<std::size_t>(S) * (S / 2));
  for (int m = 0; m < S; ++m) {
    for (int k = 0; k < S / 2; ++k) {
      const double a = 2.0 * M_PI * ((static_cast<long>(k) * m) % S) / S;
      cos_[m * (S / 2) + k] = std::cos(a);
      sin_[m * (S / 2) + k] = std::sin(a);
    }
  }
  inv_cos_.assign(static_cast<std::size_t>(K) * m_padded_, 0.f);
  inv_sin_.assign(static_cast<std::size_t>(K) * m_padded_, 0.f);
  for (int k = 0; k < K; ++k) {
    for (int s = 0; s < S; ++s) {
      const double a = 2.0 * M_PI * ((static_cast<long>(k) * s) % S) / S;
      float* row = &forward_[static_cast<std::size_t>(s) * S];
      if (k < S / 2) row[k] = static_cast<float>(std::cos(a));   // Re X_k
      if (k == S / 2) row[k] = static_cast<float>(std::cos(a));  // Re X_{S/2}, where Im X_0 is
      if (k > 0 && k < S / 2) row[S / 2 + k] = static_cast<float>(-std::sin(a));  // Im X_k
    }
    const double w = (k == 0 || 2 * k == S) ? 1.0 : 2.0;
    for (int m = 0; m < K; ++m) {
      const double a = 2.0 * M_PI * ((static_cast<long>(k) * m) % S) / S;
      inv_cos_[k * m_padded_ + m] = static_cast<float>(w * std::cos(a) / S);
      inv_sin_[k * m_padded_ + m] = static_cast<float>(-w * std::sin(a) / S);
    }
  }
}

void ScanContextSpectra::pack(const Signature& place, float* out) const {
  const int R = rings_, S = sectors_;
  if (place.rows() != 1 || place.cols() != 2 * R * S) {
    throw std::invalid_argument(
        "a Scan Context signature must be 1 x " + std::to_string(2 * R * S) + ", got " +
        std::to_string(place.rows()) + " x " + std::to_string(place.cols()));
  }
  for (int c = 0; c < 2; ++c) {
    const double* x = place.data() + static_cast<std::size_t>(c) * R * S;
    double norm2 = 0;
    for (int i = 0; i < R * S; ++i) norm2 += x[i] * x[i];
    const double scale = norm2 > 0 ? 1.0 / std::sqrt(norm2) : 0.0;
    float* o = out + static_cast<std::size_t>(c) * R * S;
    for (int r = 0; r < R; ++r) {
      // Empty cells are skipped: scans fill a fraction of them, intensity halves are 0/1.
      float* packed = o + static_cast<std::size_t>(r) * S;
      std::fill(packed, packed + S, 0.f);
      for (int s = 0; s < S; ++s) {
        const float v = static_cast<float>(x[s * R + r] * scale);  // layout: sector * R + ring
        if (v == 0.f) continue;
        scaled_accumulate(packed, &forward_[static_cast<std::size_t>(s) * S], v, S);
      }
    }
  }
}

ScanContextSpectra::Query ScanContextSpectra::prepare(const Signature& query) const {
  AlignedFloats packed(floats_per_place());
  pack(query, packed.data());
  Query q;
  prepare_packed(packed.data(), q);
  return q;
}

void ScanContextSpectra::prepare_packed(const float* packed, Query& out) const {
  const int S = sectors_, H = S / 2, n = floats_per_place();
  out.packed = AlignedFloats(n);
  std::copy(packed, packed + n, out.packed.data());
  out.swapped = AlignedFloats(n);
  for (int r = 0; r < 2 * rings_; ++r) {
    const float* in = packed + static_cast<std::size_t>(r) * S;
    float* sw = out.swapped.data() + static_cast<std::size_t>(r) * S;
    std::copy(in + H, in + S, sw);
    std::copy(in, in + H, sw + H);
  }
}

namespace {

// The pair kernel: (1) element-wise products of the packed query (and its ring-swapped copy)
// with the place, summed over the rings, give the ring-summed correlation and convolution
// spectra; (2) an inverse real DFT evaluated for shifts m, S - m, S/2 - m and S/2 + m at once
// gives the best dot. The default 60 sectors get a vectorised instantiation; other sizes a
// scalar path.
constexpr int kFastSectors = 60;

struct KernelArgs {
  int rings, sectors, m_padded;
  const float* inv_cos;  // (S/2 + 1) x m_padded, weights and 1/S folded in
  const float* inv_sin;
};

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

// best[c]: the best dot product of half c (structure, intensity) between the packed query q
// (and its ring-swapped copy qs) and the packed place p, over every shift and mirrored order;
// picked at run time for the CPU (AVX-512, AVX2+FMA or the SSE2 baseline; the same bits on the
// first two, the baseline rounds its unfused multiply-adds).
void pair_best_dots(const KernelArgs& args, const float* q, const float* qs, const float* p,
                    float best[2]) {
  static const auto kernel = simd::widest(best_dots_avx512, best_dots_avx2, best_dots_base);
  kernel(args, q, qs, p, best);
}

}  // namespace

void ScanContextSpectra::best_dots(const Query& query, const float* place, float best[2]) const {
  const KernelArgs args{rings_, sectors_, m_padded_, inv_cos_.data(), inv_sin_.data()};
  pair_best_dots(args, query.packed.data(), query.swapped.data(), place, best);
}

std::vector<ScanContextSpectra::Query> ScanContextSpectra::prepare_versions(
    const Signature& signature) const {
  std::vector<Query> versions;
  for (Eigen::Index v = 0; v < signature.rows(); ++v) versions.push_back(prepare(signature.row(v)));
  return versions;
}

void ScanContextSpectra::best_dots(const std::vector<Query>& versions, const float* place,
                                   float best[2]) const {
  best[0] = best[1] = -2.f;  // below any dot of unit vectors
  float dots[2];
  for (const Query& q : versions) {
    best_dots(q, place, dots);
    best[0] = std::max(best[0], dots[0]);
    best[1] = std::max(best[1], dots[1]);
  }
}

// The winning sector alignment of one half, in double precision: the same ring sums and
// inverse DFT as the pair kernel, kept per shift instead of reduced to the best dot (the yaw of
// a match needs the shift, the kernel only the score).
SectorAlignment ScanContextSpectra::align(const Query& query, const float* place, int half) const {
  const int R = rings_, S = sectors_, H = S / 2;
  const std::size_t off = static_cast<std::size_t>(half) * R * S;
  std::vector<double> a1(S, 0.0), a2(S, 0.0);
  for (int r = 0; r < R; ++r) {
    for (int j = 0; j < S; ++j) {
      a1[j] += double(query.packed[off + r * S + j]) * place[off + r * S + j];
      a2[j] += double(query.swapped[off + r * S + j]) * place[off + r * S + j];
    }
  }
  // c_m = (1/S) sum_k w_k (Re P_k cos(2 pi k m / S) - Im P_k sin(2 pi k m / S)).
  // Correlation c_m pairs query sector t + m with place sector t: shift = -m. Convolution c_m
  // pairs query sector s with place sector m - s: mirrored, shift = m.
  std::vector<double> re(H, 0.0), im(H, 0.0);
  SectorAlignment best{-3.0, 0, false};
  for (int mirrored = 0; mirrored < 2; ++mirrored) {
    for (int k = 1; k < H; ++k) {
      const double x = a1[k], y = a1[H + k], z = a2[k], u = a2[H + k];
      re[k] = 2.0 * (mirrored ? x - y : x + y);
      im[k] = 2.0 * (mirrored ? z + u : z - u);
    }
    for (int shift = 0; shift < S; ++shift) {
      const int m = mirrored ? shift : (S - shift) % S;
      const double* cs = &cos_[static_cast<std::size_t>(m) * H];
      const double* sn = &sin_[static_cast<std::size_t>(m) * H];
      double c = a1[0] + ((m % 2) ? -a1[H] : a1[H]);
      for (int k = 1; k < H; ++k) c += re[k] * cs[k] - im[k] * sn[k];
      c /= S;
      if (c > best.dot) best = {c, shift, mirrored != 0};
    }
  }
  return best;
}

}  // namespace loopscan
