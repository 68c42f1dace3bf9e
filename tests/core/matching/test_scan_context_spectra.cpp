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
      std::vector<float> packed(spectra.floats_per_place());
      spectra.pack(b, packed.data());
      const auto q = spectra.prepare(a);
      float best[2];
      spectra.best_dots(q, packed.data(), best);
      for (int c = 0; c < 2; ++c) {
        const double d = oracle(Method::ScanContext, a, b, Component(c), cfg);
        EXPECT_NEAR((1.0 - best[c]) / 2.0, d, 2e-5) << "S=" << sectors << " c=" << c;
        if (trial % 4 == 0 && c == 1) continue;
        const SectorAlignment al = spectra.align(q, packed.data(), c);
        EXPECT_NEAR(al.dot, 1.0 - 2.0 * d, 2e-5);
        EXPECT_NEAR(dot_at(a, b, c, al.shift, al.mirrored, cfg), al.dot, 2e-5)
            << "shift " << al.shift << (al.mirrored ? " mirrored" : "");
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
