#include "loopscan/core/matching/birds_eye_match.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>

#include "loopscan/core/simd.hpp"

namespace loopscan {
namespace {

double squared_norm(const std::vector<std::int8_t>& v) {
  double s = 0;
  for (std::int8_t x : v) s += double(x) * double(x);
  return s;
}

// The key's DFT along its angles: cos and -sin of 2 pi k a / A for a < A, k <= A / 2.
struct KeyTransform {
  int angles = 0;
  std::vector<double> cos, minus_sin;  // angles x (A / 2 + 1)
};

const KeyTransform& key_transform(int angles) {
  thread_local KeyTransform t;
  if (t.angles == angles) return t;
  t.angles = angles;
  const int terms = angles / 2 + 1;
  t.cos.resize(std::size_t(angles) * terms);
  t.minus_sin.resize(std::size_t(angles) * terms);
  for (int a = 0; a < angles; ++a) {
    for (int k = 0; k < terms; ++k) {
      const double turn = 2 * M_PI * double((std::int64_t(k) * a) % angles) / angles;
      t.cos[std::size_t(a) * terms + k] = std::cos(turn);
      t.minus_sin[std::size_t(a) * terms + k] = -std::sin(turn);
    }
  }
  return t;
}

// The inverse transform of a cross spectrum, per term k and shift s < H: w_k cos(2 pi k s / A)
// and w_k sin(..), w_k counting the conjugate-symmetric half twice. For even A only the first
// H = A / 2 shifts are tabled: corr(s + H) = E(s) - O(s) where corr(s) = E(s) + O(s), E and O
// the sums over even and odd terms.
struct ShiftTables {
  int angles = 0, terms = 0, half = 0, padded = 0;  // padded: shifts rounded up to kLanes
  std::vector<float> cos, sin;                        // terms x padded
};
constexpr int kLanes = simd::kChunkLanes<float> * 2;  // the widest kernel's lanes (16)

const ShiftTables& shift_tables(int angles) {
  thread_local ShiftTables t;
  if (t.angles == angles) return t;
  t.angles = angles;
  t.terms = angles / 2 + 1;
  t.half = angles % 2 == 0 ? angles / 2 : angles;
  t.padded = (t.half + kLanes - 1) / kLanes * kLanes;
  t.cos.assign(std::size_t(t.terms) * t.padded, 0.f);
  t.sin.assign(std::size_t(t.terms) * t.padded, 0.f);
  for (int k = 0; k < t.terms; ++k) {
    const double w = (k == 0 || 2 * k == angles) ? 1.0 : 2.0;
    for (int s = 0; s < t.half; ++s) {
      const double a = 2 * M_PI * double((std::int64_t(k) * s) % angles) / angles;
      t.cos[std::size_t(k) * t.padded + s] = float(w * std::cos(a));
      t.sin[std::size_t(k) * t.padded + s] = float(w * std::sin(a));
    }
  }
  return t;
}

constexpr int kMaxAngles = 720;

// The cross spectrum of two keys summed over rings, X_k = sum_r Q_rk conj(D_rk), as real and
// imaginary parts of stride floats; from the place's bfloat16 copy where `Rounded`. W: the
// vector width in bytes.
template <int W, bool Rounded>
LOOPSCAN_INLINE void cross_spectrum_impl(const BirdsEyeKeySpectrumView& q,
                                         const BirdsEyeKeySpectrumView& d, float* xr, float* xi) {
  using V = typename simd::Vec<float, W>::type;
  using U = typename simd::Vec<std::uint32_t, W>::type;
  using H = typename simd::Vec<std::uint16_t, W / 2>::type;
  constexpr int L = simd::Vec<float, W>::kLanes;
  const int stride = q.stride, blocks = stride / L;
  const std::size_t parts = std::size_t(d.rings) * stride;  // the rounded copy's real parts
  for (int b = 0; b < blocks; ++b) {
    V ar{}, ai{};
    for (int r = 0; r < q.rings; ++r) {
      const std::size_t o = std::size_t(r) * stride + std::size_t(b) * L;
      const V qr = simd::load<V>(q.re + o), qi = simd::load<V>(q.im + o);
      V dr, di;
      if constexpr (Rounded) {  // a bfloat16 is a float's upper 16 bits
        dr = V(__builtin_convertvector(simd::load<H>(d.rounded + o), U) << 16);
        di = V(__builtin_convertvector(simd::load<H>(d.rounded + parts + o), U) << 16);
      } else {
        dr = simd::load<V>(d.re + o);
        di = simd::load<V>(d.im + o);
      }
      ar += qr * dr + qi * di;
      ai += qi * dr - qr * di;
    }
    simd::store(xr + b * L, ar);
    simd::store(xi + b * L, ai);
  }
}

// The cross spectrum's bound on every shift's correlation, sum_k w_k |X_k| (w_k as in the
// tables).
float spectrum_bound(const float* xr, const float* xi, int terms, int angles) {
  float bound = 0;
  for (int k = 0; k < terms; ++k) {
    const float w = (k == 0 || 2 * k == angles) ? 1.f : 2.f;
    bound += w * std::sqrt(xr[k] * xr[k] + xi[k] * xi[k]);
  }
  return bound;
}

// The inverse transform of a cross spectrum: the correlation at every shift (out[s], s < A).
template <int W>
LOOPSCAN_INLINE void shift_correlations_impl(const float* xr, const float* xi, const ShiftTables& t,
                                             float* out) {
  using V = typename simd::Vec<float, W>::type;
  constexpr int L = simd::Vec<float, W>::kLanes;
  const int sblocks = t.padded / L;
  alignas(64) float even[kMaxAngles + kLanes], odd[kMaxAngles + kLanes];
  const bool fold = t.half != t.angles;
  for (int j = 0; j < sblocks; ++j) {
    V e{}, o{};
    for (int k = 0; k < t.terms; ++k) {
      const std::size_t at = std::size_t(k) * t.padded + std::size_t(j) * L;
      const V term = xr[k] * simd::load<V>(t.cos.data() + at) - xi[k] * simd::load<V>(t.sin.data() + at);
      if (fold && (k & 1)) {
        o += term;
      } else {
        e += term;
      }
    }
    simd::store(even + j * L, e);
    simd::store(odd + j * L, o);
  }
  for (int s = 0; s < t.half; ++s) out[s] = even[s] + odd[s];
  if (fold) {
    for (int s = 0; s < t.half; ++s) out[t.half + s] = even[s] - odd[s];
  }
}

// Every shift's correlation when `out` is given; else only the cross spectrum's bound on it
// (spectrum_bound), from the place's bfloat16 copy where it has one: no shift's correlation
// can exceed it (up to that copy's rounding).
template <int W>
LOOPSCAN_INLINE float key_correlations_impl(const BirdsEyeKeySpectrumView& q,
                                            const BirdsEyeKeySpectrumView& d, const ShiftTables& t,
                                            float* out) {
  alignas(64) float xr[kMaxAngles / 2 + kLanes], xi[kMaxAngles / 2 + kLanes];
  if (out) {
    cross_spectrum_impl<W, false>(q, d, xr, xi);
    shift_correlations_impl<W>(xr, xi, t, out);
    return 0;
  }
  if (d.rounded) {
    cross_spectrum_impl<W, true>(q, d, xr, xi);
  } else {
    cross_spectrum_impl<W, false>(q, d, xr, xi);
  }
  return spectrum_bound(xr, xi, t.terms, t.angles);
}

float key_correlations_base(const BirdsEyeKeySpectrumView& q, const BirdsEyeKeySpectrumView& d,
                            const ShiftTables& t, float* out) {
  return key_correlations_impl<16>(q, d, t, out);
}
#if LOOPSCAN_HAVE_AVX2_CLONES
LOOPSCAN_AVX2 float key_correlations_avx2(const BirdsEyeKeySpectrumView& q,
                                          const BirdsEyeKeySpectrumView& d, const ShiftTables& t,
                                          float* out) {
  return key_correlations_impl<32>(q, d, t, out);
}
LOOPSCAN_AVX512 float key_correlations_avx512(const BirdsEyeKeySpectrumView& q,
                                              const BirdsEyeKeySpectrumView& d,
                                              const ShiftTables& t, float* out) {
  return key_correlations_impl<64>(q, d, t, out);
}
#endif

float key_correlations(const BirdsEyeKeySpectrumView& q, const BirdsEyeKeySpectrumView& d,
                       const ShiftTables& t, float* out) {
#if LOOPSCAN_HAVE_AVX2_CLONES
  static const auto kernel =
      simd::widest(key_correlations_avx512, key_correlations_avx2, key_correlations_base);
#else
  static const auto kernel = key_correlations_base;
#endif
  return kernel(q, d, t, out);
}

void check_spectra(const BirdsEyeKeySpectrumView& query, const BirdsEyeKeySpectrumView& place) {
  if (query.rings != place.rings || query.angles != place.angles || query.angles < 2 ||
      query.angles > kMaxAngles || query.stride != key_spectrum_stride(query.angles) ||
      place.stride != query.stride) {
    throw std::invalid_argument("birds_eye: key spectra of the same rings and angles expected");
  }
}

}  // namespace

BirdsEyeKeyMatch match_keys(const BirdsEyePlace& query, const BirdsEyePlace& place, int angles) {
  if (angles < 1 || query.key.size() != place.key.size() || query.key.size() % angles != 0) {
    throw std::invalid_argument("birds_eye: keys of equal size, whole rings of " +
                                std::to_string(angles) + " angles expected");
  }
  BirdsEyeKeyMatch best;
  const double norms = std::sqrt(squared_norm(query.key) * squared_norm(place.key));
  if (!(norms > 0)) return best;
  const int rings = int(query.key.size()) / angles;
  const std::int8_t* q = query.key.data();
  const std::int8_t* d = place.key.data();
  double top = -1e300;
  int top_shift = 0;
  for (int shift = 0; shift < angles; ++shift) {  // q[a] against d[a - shift]
    long long sum = 0;
    for (int r = 0; r < rings; ++r) {
      const std::int8_t* qr = q + std::size_t(r) * angles;
      const std::int8_t* dr = d + std::size_t(r) * angles;
      for (int a = 0; a < shift; ++a) sum += int(qr[a]) * int(dr[a - shift + angles]);
      for (int a = shift; a < angles; ++a) sum += int(qr[a]) * int(dr[a - shift]);
    }
    if (double(sum) > top) {
      top = double(sum);
      top_shift = shift;
    }
  }
  best.distance = 1.0 - top / norms;
  best.yaw_rad = top_shift * M_PI / angles;
  return best;
}

BirdsEyeKeySpectrum key_spectrum(const BirdsEyePlace& place, int angles) {
  if (angles < 2 || angles > kMaxAngles || place.key.size() % std::size_t(angles) != 0) {
    throw std::invalid_argument("birds_eye: a key of whole rings of " + std::to_string(angles) +
                                " angles (2 to " + std::to_string(kMaxAngles) + ") expected");
  }
  BirdsEyeKeySpectrum s;
  s.rings = int(place.key.size()) / angles;
  s.angles = angles;
  const int terms = angles / 2 + 1;
  s.stride = key_spectrum_stride(angles);
  s.re.assign(std::size_t(s.rings) * s.stride, 0.f);
  s.im.assign(std::size_t(s.rings) * s.stride, 0.f);
  s.norm = std::sqrt(squared_norm(place.key));
  // Per ring, the terms of all frequencies together: out[k] += v[a] e^{-2 pi i k a / A}, a loop
  // over k that vectorises.
  const KeyTransform& transform = key_transform(angles);
  std::vector<double> re(terms), im(terms);
  for (int r = 0; r < s.rings; ++r) {
    const std::int8_t* v = place.key.data() + std::size_t(r) * angles;
    std::fill(re.begin(), re.end(), 0.0);
    std::fill(im.begin(), im.end(), 0.0);
    for (int a = 0; a < angles; ++a) {
      const double value = v[a];
      const double* c = transform.cos.data() + std::size_t(a) * terms;
      const double* sn = transform.minus_sin.data() + std::size_t(a) * terms;
      for (int k = 0; k < terms; ++k) {
        re[k] += value * c[k];
        im[k] += value * sn[k];
      }
    }
    for (int k = 0; k < terms; ++k) {
      s.re[std::size_t(r) * s.stride + k] = float(re[k]);
      s.im[std::size_t(r) * s.stride + k] = float(im[k]);
    }
  }
  s.rounded.reserve(s.re.size() + s.im.size());
  for (const std::vector<float>* part : {&s.re, &s.im}) {
    for (float v : *part) {
      std::uint32_t bits;
      std::memcpy(&bits, &v, sizeof bits);
      bits += 0x7fffu + ((bits >> 16) & 1u);  // to nearest, ties to even (finite values)
      s.rounded.push_back(std::uint16_t(bits >> 16));
    }
  }
  return s;
}

void pack_key_spectrum(const BirdsEyeKeySpectrum& spectrum, float* out) {
  out[0] = static_cast<float>(spectrum.norm);
  std::copy(spectrum.re.begin(), spectrum.re.end(), out + 1);
  std::copy(spectrum.im.begin(), spectrum.im.end(), out + 1 + spectrum.re.size());
}

BirdsEyeKeyMatch match_key_spectra(const BirdsEyeKeySpectrumView& query,
                                   const BirdsEyeKeySpectrumView& place) {
  check_spectra(query, place);
  BirdsEyeKeyMatch best;
  const double norms = query.norm * place.norm;
  if (!(norms > 0)) return best;
  const int A = query.angles;
  alignas(64) float corr[kMaxAngles];
  key_correlations(query, place, shift_tables(A), corr);
  const int top = int(std::max_element(corr, corr + A) - corr);  // the first of ties
  best.distance = 1.0 - corr[top] / (A * norms);
  best.yaw_rad = top * M_PI / A;
  return best;
}

std::vector<std::pair<double, std::size_t>> nearest_keys(
    const BirdsEyeKeySpectrumView& query, std::size_t places,
    const std::function<bool(std::size_t)>& eligible,
    const std::function<BirdsEyeKeySpectrumView(std::size_t)>& spectrum, std::size_t count) {
  std::vector<std::pair<double, std::size_t>> bounds;  // (lower bound on the distance, place)
  if (count == 0) return bounds;
  const ShiftTables& t = shift_tables(query.angles);
  for (std::size_t i = 0; i < places; ++i) {
    if (!eligible(i)) continue;
    const BirdsEyeKeySpectrumView d = spectrum(i);
    check_spectra(query, d);
    const double norms = query.norm * d.norm;
    // Float sums may round a shift's correlation a little above the bound: widen it. A rounded
    // spectrum D' = D + E, |E_rk| <= 2^-8 |D_rk|, moves sum_k w_k |X_k| by at most
    // 2^-8 sum_k w_k sum_r |Q_rk| |D_rk| <= 2^-8 A |q| |d| (Cauchy-Schwarz, then Parseval).
    const double rounding = d.rounded ? 0.004 : 0.0;
    const double bound =
        norms > 0
            ? 1.0 - 1.0001 * key_correlations(query, d, t, nullptr) / (query.angles * norms) -
                  rounding
            : 1.0;
    bounds.emplace_back(bound, i);
  }
  // Places in order of their bound (popped from a min-heap: the loop usually stops after a
  // few), exactly matched until no bound can beat the count-th best distance: what matching
  // every place and sorting (distance, place) gives.
  const auto later = [](const auto& a, const auto& b) { return a > b; };
  std::make_heap(bounds.begin(), bounds.end(), later);
  std::vector<std::pair<double, std::size_t>> best;  // a max-heap of the count best
  while (!bounds.empty()) {
    std::pop_heap(bounds.begin(), bounds.end(), later);
    const auto [bound, i] = bounds.back();
    bounds.pop_back();
    if (best.size() == count && bound > best.front().first) break;
    const std::pair<double, std::size_t> found{match_key_spectra(query, spectrum(i)).distance, i};
    if (best.size() < count) {
      best.push_back(found);
      std::push_heap(best.begin(), best.end());
    } else if (found < best.front()) {
      std::pop_heap(best.begin(), best.end());
      best.back() = found;
      std::push_heap(best.begin(), best.end());
    }
  }
  std::sort_heap(best.begin(), best.end());
  return best;
}

}  // namespace loopscan
