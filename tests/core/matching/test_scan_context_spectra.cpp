// The packed Scan Context spectra and their pair kernel against the definition: best dot
// products and alignments over every shift, mirrored or not.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "loopscan/core/database/database.hpp"
#include "loopscan/core/database/key_index.hpp"
#include "loopscan/core/descriptors/describe.hpp"
#include "loopscan/core/matching/fusion.hpp"
#include "loopscan/core/matching/pair_distance.hpp"
#include "loopscan/core/matching/scan_context_spectra.hpp"
#include "support/random_signatures.hpp"
#include "support/test_support.hpp"

namespace loopscan {
namespace {

using test::oracle;
using test::random_signature;

// Dot of the normalised halves at a given alignment, straight from the definition.
double dot_at(const Signature& q, const Signature& d, int half, int shift, bool mirrored,
              const ScanContextConfig& c) {
  const int R = c.rings, S = c.sectors, off = half * R * S;
  const double nq = q.middleCols(off, R * S).norm(), nd = d.middleCols(off, R * S).norm();
  double dot = 0;
  for (int s = 0; s < S; ++s) {
    const int t = mirrored ? ((shift - s) % S + S) % S : (s + shift) % S;
    for (int r = 0; r < R; ++r) dot += q(0, off + s * R + r) * d(0, off + t * R + r);
  }
  return dot / (nq * nd);
}

TEST(ScanContextSpectra, BestDotsAndAlignmentMatchTheOracle) {
  for (int sectors : {60, 36}) {  // the vectorised and the generic path
    ScanContextConfig cfg;
    cfg.sectors = sectors;
    cfg.rings = sectors == 60 ? 20 : 7;
    const ScanContextSpectra spectra(cfg);
    std::mt19937 rng(sectors);
    for (int trial = 0; trial < 20; ++trial) {
      const Signature a = random_signature(Method::ScanContext, rng, cfg);
      Signature b = random_signature(Method::ScanContext, rng, cfg);
      if (trial % 4 == 0) b.rightCols(b.cols() / 2).setZero();  // a zero half
      if (trial % 4 == 2) {  // a's sectors shifted, a few cells changed: a dot near 1
        const int R = cfg.rings, S = sectors, shift = (7 * trial) % S;
        for (int h = 0; h < 2; ++h) {
          for (int i = 0; i < R * S; ++i) {
            b(0, h * R * S + ((i / R + shift) % S) * R + i % R) = a(0, h * R * S + i);
          }
        }
        for (int i = 0; i < 10; ++i) b(0, (37 * i + trial) % (R * S)) += 0.5;
      }
      std::vector<float> packed(spectra.floats_per_place());
      spectra.pack(b, packed.data());
      const auto q = spectra.prepare(a);
      float best[2];
      spectra.best_dots(q, packed.data(), best);
      for (int c = 0; c < 2; ++c) {
        const double d = oracle(Method::ScanContext, a, b, Component(c), cfg);
        EXPECT_NEAR((1.0 - best[c]) / 2.0, d, 2e-5) << "S=" << sectors << " c=" << c;
        if (trial % 4 == 0 && c == 1) continue;
        // Brute force over every shift and order: the kernel's dot within 1e-5 of the best
        // one, the alignment's shift the best one or tied with it within 1e-5.
        double top = -2.0;
        for (int m = 0; m < 2 * sectors; ++m) {
          top = std::max(top, dot_at(a, b, c, m % sectors, m >= sectors, cfg));
        }
        EXPECT_NEAR(best[c], top, 1e-5) << "S=" << sectors << " c=" << c;
        const SectorAlignment al = spectra.align(q, packed.data(), c);
        EXPECT_NEAR(al.dot, 1.0 - 2.0 * d, 2e-5);
        EXPECT_NEAR(dot_at(a, b, c, al.shift, al.mirrored, cfg), al.dot, 2e-5)
            << "shift " << al.shift << (al.mirrored ? " mirrored" : "");
        EXPECT_GE(dot_at(a, b, c, al.shift, al.mirrored, cfg), top - 1e-5);
      }
    }
  }
}

TEST(ScanContextSpectra, RejectsOddSectorsAndWrongShapes) {
  ScanContextConfig odd;
  odd.sectors = 61;
  EXPECT_THROW(ScanContextSpectra{odd}, std::invalid_argument);
  const ScanContextSpectra spectra(ScanContextConfig{});
  std::vector<float> out(spectra.floats_per_place());
  EXPECT_THROW(spectra.pack(Signature::Zero(1, 100), out.data()), std::invalid_argument);
}

}  // namespace
}  // namespace loopscan
