#pragma once
// Random signatures of each method's shape and the straightforward pair distances, for the
// matching and database oracle tests.
#include <cmath>
#include <random>

#include "loopscan/core/config.hpp"
#include "loopscan/core/matching/pair_distance.hpp"
#include "loopscan/core/signature.hpp"

namespace loopscan::test {

// Random signatures of the method's shape: sparse non-negative SC heights with 0/1
// intensities, signed M2DP rows, sparse DELIGHT counts.
inline Signature random_signature(Method m, std::mt19937& rng, const ScanContextConfig& sc = {}) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  if (m == Method::ScanContext) {
    const int n = sc.rings * sc.sectors;
    Signature s = Signature::Zero(1, 2 * n);
    for (int i = 0; i < n; ++i) {
      if (u(rng) < 0.5) continue;
      s(0, i) = 5 * u(rng);
      s(0, n + i) = u(rng) < 0.5 ? 1.0 : 0.0;
    }
    return s;
  }
  if (m == Method::M2dp) {
    Signature s(4, signature_columns(m));
    for (Eigen::Index i = 0; i < s.size(); ++i) s(i) = u(rng) - 0.5;
    return s;
  }
  Signature s = Signature::Zero(16, signature_columns(m));
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    if (u(rng) < 0.2) s(i) = std::floor(10 * u(rng));
  }
  return s;
}

// The straightforward pair distance of each method (the oracle of the fast paths).
inline double oracle(Method m, const Signature& q, const Signature& d, Component c,
                     const ScanContextConfig& sc = {}) {
  if (m == Method::ScanContext) return scan_context_distance(q, d, c, sc);
  if (m == Method::M2dp) return m2dp_distance(q, d, c);
  return delight_distance(q, d);
}

}  // namespace loopscan::test
