// Pair kernel: (1) element-wise products of the packed query (and its ring-swapped copy) with
// the place, summed over the rings, give the ring-summed correlation and convolution spectra;
// (2) an inverse real DFT evaluated for shifts m and S - m at once (A + B and A - B) gives the
// best dot. The default 60 sectors get a vectorised instantiation; other sizes a scalar path.
#include "loopscan/core/matching/scan_context_spectra.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "loopscan/core/simd.hpp"

namespace loopscan {
namespace {

constexpr int kMaxSectors = 512;
constexpr int kFastSectors = 60;

// Scalar ring sums: a[j] = sum_r q[r S + j] p[r S + j].
void ring_sums_scalar(const float* q, const float* p, int rings, int S, float* a) {
  std::fill(a, a + S, 0.f);
  for (int r = 0; r < rings; ++r) {
    for (int j = 0; j < S; ++j) a[j] += q[r * S + j] * p[r * S + j];
  }
}

// Both ring sums for S = 60 with vectors: a block of lcm(S, lanes) floats is 15 vectors; five
// of them at a time keep 10 accumulators in registers and load each place vector once for
// the two products. The blocks are folded back to S sums at the end.
template <int W>
LOOPSCAN_INLINE void ring_sums_60(const float* q, const float* qs, const float* p, int rings,
                                  float* a1, float* a2) {
  using V = typename simd::Vec<float, W>::type;
  constexpr int kV = simd::Vec<float, W>::kLanes, kNV = 15, kBlock = kNV * kV, kGroup = 5;
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

// max over m <= S/2 of A_m + |B_m| with A = sum_k re_k ic[k][m], B = sum_k im_k is[k][m]:
// shifts m and S - m are A + B and A - B.
template <int W, int MV>
LOOPSCAN_INLINE float best_of_inverse(const float* re, const float* im, int K, const float* ic,
                                      const float* is, int M) {
  using V = typename simd::Vec<float, W>::type;
  constexpr int kV = simd::Vec<float, W>::kLanes, kMP = MV * kV;
  V A[MV], B[MV];
  for (int v = 0; v < MV; ++v) A[v] = B[v] = V{};
  for (int k = 0; k < K; ++k) {
    const float a = re[k], b = im[k];
    for (int v = 0; v < MV; ++v) {
      A[v] += a * simd::load<V>(ic + k * kMP + v * kV);
      B[v] += b * simd::load<V>(is + k * kMP + v * kV);
    }
  }
  // Lanes m >= M are padding (zero tables): pushed far below any dot product.
  V best = A[0] + (B[0] < 0 ? -B[0] : B[0]);
  for (int v = 1; v < MV; ++v) {
    V x = A[v] + (B[v] < 0 ? -B[v] : B[v]);
    if ((v + 1) * kV > M) {
      for (int l = 0; l < kV; ++l) {
        if (v * kV + l >= M) x[l] = -1e30f;
      }
    }
    best = best > x ? best : x;
  }
  float m = best[0];
  for (int l = 1; l < kV; ++l) m = m > best[l] ? m : best[l];
  return m;
}

// Both spectra (correlation c, convolution v) in one pass: eight chains of multiply-adds
// instead of four (a 64-byte W has only two vectors of m), each lane summing in the same order.
template <int W, int MV>
LOOPSCAN_INLINE float best_of_inverse_pair(const float* cre, const float* cim, const float* vre,
                                           const float* vim, int K, const float* ic,
                                           const float* is, int M) {
  using V = typename simd::Vec<float, W>::type;
  constexpr int kV = simd::Vec<float, W>::kLanes, kMP = MV * kV;
  V A[MV], B[MV], C[MV], D[MV];
  for (int v = 0; v < MV; ++v) A[v] = B[v] = C[v] = D[v] = V{};
  for (int k = 0; k < K; ++k) {
    const float a = cre[k], b = cim[k], c = vre[k], d = vim[k];
    for (int v = 0; v < MV; ++v) {
      const V icv = simd::load<V>(ic + k * kMP + v * kV),
              isv = simd::load<V>(is + k * kMP + v * kV);
      A[v] += a * icv;
      B[v] += b * isv;
      C[v] += c * icv;
      D[v] += d * isv;
    }
  }
  V best = V{} - 1e30f;
  for (int v = 0; v < MV; ++v) {
    V x = A[v] + (B[v] < 0 ? -B[v] : B[v]);
    V y = C[v] + (D[v] < 0 ? -D[v] : D[v]);
    x = x > y ? x : y;
    for (int l = 0; l < kV; ++l) {
      if (v * kV + l >= M) x[l] = -1e30f;  // padding lanes
    }
    best = best > x ? best : x;
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

struct KernelArgs {
  int rings, sectors, m_padded;
  const float* inv_cos;
  const float* inv_sin;
};

// W: the inverse DFT's vector width; the ring sums stay at most 32 bytes wide, so a wider
// instantiation sums in the same order and gives the same bits (its lanes are independent).
template <int W>
LOOPSCAN_INLINE void best_dots_impl(const KernelArgs& k, const float* q, const float* qs,
                                    const float* p, float best[2]) {
  const int S = k.sectors, R = k.rings, H = S / 2, K = H + 1;
  const bool fast = S == kFastSectors;
  constexpr int kMV = 32 / simd::Vec<float, W>::kLanes;  // 32 padded m for S = 60
  constexpr int kSumW = W < 32 ? W : 32;
  float a1[kMaxSectors], a2[kMaxSectors];
  float cre[kMaxSectors / 2 + 1], cim[kMaxSectors / 2 + 1];
  float vre[kMaxSectors / 2 + 1], vim[kMaxSectors / 2 + 1];
  for (int c = 0; c < 2; ++c) {
    const std::size_t off = static_cast<std::size_t>(c) * R * S;
    if (fast) {
      ring_sums_60<kSumW>(q + off, qs + off, p + off, R, a1, a2);
    } else {
      ring_sums_scalar(q + off, p + off, R, S, a1);
      ring_sums_scalar(qs + off, p + off, R, S, a2);
    }
    cross_spectra(a1, a2, S, cre, cim, vre, vim);
    if (fast && W == 64) {
      best[c] = best_of_inverse_pair<W, kMV>(cre, cim, vre, vim, K, k.inv_cos, k.inv_sin, K);
    } else if (fast) {
      best[c] = std::max(best_of_inverse<W, kMV>(cre, cim, K, k.inv_cos, k.inv_sin, K),
                         best_of_inverse<W, kMV>(vre, vim, K, k.inv_cos, k.inv_sin, K));
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
        const float* row = &forward_[static_cast<std::size_t>(s) * S];
        for (int k = 0; k < S; ++k) packed[k] += v * row[k];
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

void ScanContextSpectra::best_dots(const Query& query, const float* place, float best[2]) const {
  static const auto kernel = simd::has_avx512() ? best_dots_avx512
                             : simd::has_avx2() ? best_dots_avx2
                                                : best_dots_base;
  const KernelArgs args{rings_, sectors_, m_padded_, inv_cos_.data(), inv_sin_.data()};
  kernel(args, query.packed.data(), query.swapped.data(), place, best);
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

}  // namespace loopscan
