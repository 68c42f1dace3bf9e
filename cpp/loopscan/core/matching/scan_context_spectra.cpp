// Packing of Scan Context places into real spectra along the sectors, queries, the pair
// kernel's dispatch (scan_context_pair_kernel.cpp) and the double-precision alignment.
#include "loopscan/core/matching/scan_context_spectra.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "loopscan/core/matching/scan_context_pair_kernel.hpp"
#include "loopscan/core/matching/scaled_accumulate.hpp"

namespace loopscan {
namespace {

constexpr int kMaxSectors = kMaxSpectraSectors;

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

void ScanContextSpectra::best_dots(const Query& query, const float* place, float best[2]) const {
  const ScanContextPairArgs args{rings_, sectors_, m_padded_, inv_cos_.data(), inv_sin_.data()};
  scan_context_pair_best_dots(args, query.packed.data(), query.swapped.data(), place, best);
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
