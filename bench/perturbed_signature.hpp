#pragma once
// A perturbed copy of a place's signature for the database benchmarks' large maps: each
// non-zero cell scaled by 1 + 0.1 N(0,1), 10% of them emptied (Scan Context: intensities stay
// 0/1), and for Scan Context a random roll of the sectors (a different heading).
#include <random>

#include "loopscan/core/config.hpp"
#include "loopscan/core/signature.hpp"

namespace loopscan::bench {

inline Signature perturbed(Method m, const Signature& s, std::mt19937& rng) {
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Signature out = s;
  for (Eigen::Index i = 0; i < out.size(); ++i) {
    if (out(i) == 0) continue;
    out(i) = u(rng) < 0.1 ? 0.0 : out(i) * (1.0 + 0.1 * n01(rng));
    if (m == Method::ScanContext && i >= out.size() / 2) out(i) = out(i) != 0 ? 1.0 : 0.0;
  }
  if (m == Method::ScanContext) {  // roll the sectors: a different heading
    const int R = 20, S = 60, shift = static_cast<int>(u(rng) * S);
    Signature rolled = out;
    for (int h = 0; h < 2; ++h) {
      for (int sct = 0; sct < S; ++sct) {
        for (int r = 0; r < R; ++r) {
          rolled(0, h * R * S + ((sct + shift) % S) * R + r) = out(0, h * R * S + sct * R + r);
        }
      }
    }
    out = rolled;
  }
  return out;
}

}  // namespace loopscan::bench
