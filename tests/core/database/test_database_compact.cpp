// Compact Scan Context places (bytes + a scale per ring) against full ones, and the two-pass
// scoring of indexed candidates (proposing versions first, every version for the best few)
// against scoring every candidate with every version.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>

#include "loopscan/core/database/compact_spectra.hpp"
#include "loopscan/core/database/database.hpp"
#include "support/random_signatures.hpp"

namespace loopscan {
namespace {

using test::random_signature;

TEST(CompactSpectra, RoundTripIsWithinHalfAStepAndEmptyRowsStayZero) {
  std::mt19937 rng(1);
  std::normal_distribution<float> g;
  const CompactSpectraShape shape{6, 60};
  std::vector<float> packed(shape.packed_floats()), compact(shape.floats()), back(packed.size());
  for (int trial = 0; trial < 20; ++trial) {
    for (float& v : packed) v = g(rng) * (trial % 4 == 0 ? 1e-6f : 3.f);
    std::fill(packed.begin() + 60, packed.begin() + 120, 0.f);  // row 1 empty
    compress_spectra(shape, packed.data(), compact.data());
    expand_spectra(shape, compact.data(), back.data());
    for (int r = 0; r < shape.rows; ++r) {
      float peak = 0;
      for (int k = 0; k < 60; ++k) peak = std::max(peak, std::abs(packed[r * 60 + k]));
      EXPECT_FLOAT_EQ(compact[r], peak / 127.f);
      for (int k = 0; k < 60; ++k) {
        const float err = std::abs(back[r * 60 + k] - packed[r * 60 + k]);
        EXPECT_LE(err, 0.5f * peak / 127.f * 1.0001f) << "row " << r << " value " << k;
      }
    }
    for (int k = 60; k < 120; ++k) EXPECT_EQ(back[k], 0.f);
  }
}

// Every SIMD width expands a value to exactly scale x byte (sectors not a multiple of 16 too).
TEST(CompactSpectra, ExpansionIsScaleTimesByteBitForBit) {
  std::mt19937 rng(2);
  std::normal_distribution<float> g;
  for (int sectors : {2, 10, 16, 20, 60, 62}) {
    const CompactSpectraShape shape{5, sectors};
    std::vector<float> packed(shape.packed_floats()), compact(shape.floats()), back(packed.size());
    for (float& v : packed) v = g(rng);
    compress_spectra(shape, packed.data(), compact.data());
    expand_spectra(shape, compact.data(), back.data());
    const auto* bytes = reinterpret_cast<const std::int8_t*>(compact.data() + shape.rows);
    for (std::size_t i = 0; i < back.size(); ++i) {
      const float want = compact[i / sectors] * static_cast<float>(bytes[i]);
      ASSERT_EQ(std::memcmp(&back[i], &want, sizeof want), 0) << "sectors " << sectors << " " << i;
    }
  }
}

// Two databases of the same places, full and compact, per fusion.
struct Pair {
  Database full, compact;
  explicit Pair(Fusion f)
      : full(config(f, PlaceStorage::Full)), compact(config(f, PlaceStorage::Compact)) {}
  static DatabaseConfig config(Fusion f, PlaceStorage s) {
    DatabaseConfig c;
    c.fusion = f;
    c.storage = s;
    return c;
  }
};

TEST(CompactDatabase, DistancesAreTheFullOnesUpToTheRoundingAndRankingsAgree) {
  std::mt19937 rng(9);
  std::normal_distribution<double> noise(0.0, 0.1);
  std::vector<Signature> places;
  for (int i = 0; i < 300; ++i) places.push_back(random_signature(Method::ScanContext, rng));
  QueryOptions exact;
  exact.retrieval = Retrieval::Exact;
  double worst = 0;
  for (Fusion f : {Fusion::Structure, Fusion::Intensity, Fusion::Fused}) {
    Pair db(f);
    for (int i = 0; i < 300; ++i) {
      db.full.add({0, i}, {places[i]});
      db.compact.add({0, i}, {places[i]});
    }
    EXPECT_LT(db.compact.memory_bytes() * 3, db.full.memory_bytes());
    for (int i = 0; i < 300; i += 15) {
      Signature q = places[i];  // a noisy copy of place i
      for (Eigen::Index j = 0; j < q.size() / 2; ++j) q(j) = std::max(0.0, q(j) * (1 + noise(rng)));
      const auto a = db.full.query({q}, 300, exact), b = db.compact.query({q}, 300, exact);
      ASSERT_EQ(a.size(), 300u);
      ASSERT_EQ(b.size(), 300u);
      EXPECT_EQ(a[0].index, b[0].index);
      EXPECT_EQ(b[0].index, static_cast<std::size_t>(i));
      std::vector<double> full_by_index(300);
      for (const Candidate& c : a) full_by_index[c.index] = c.distance;
      for (const Candidate& c : b) {
        const double err = std::abs(c.distance - full_by_index[c.index]);
        worst = f == Fusion::Fused ? worst : std::max(worst, err);
        // Raw halves: (1 - dot) / 2 moves by under 1e-3; z-scores divide that by the row's
        // spread (~0.02 for random places), so fused distances move by under 0.1.
        EXPECT_LE(err, f == Fusion::Fused ? 0.1 : 1e-3) << fusion_name(f);
      }
    }
  }
  RecordProperty("worst_raw_distance_error", std::to_string(worst));
}

// A query with lateral versions (extra rows): random rows, so each version's index search
// proposes other places and the first pass really is partial.
Signature with_versions(const Signature& place, std::mt19937& rng) {
  Signature s(5, place.cols());
  s.row(0) = place.row(0);
  for (int v = 1; v < 5; ++v) s.row(v) = random_signature(Method::ScanContext, rng).row(0);
  return s;
}

TEST(CompactDatabase, RefiningTheBestFewGivesTheirAllVersionDistances) {
  for (PlaceStorage storage : {PlaceStorage::Full, PlaceStorage::Compact}) {
    std::mt19937 rng(21);
    Database db(Pair::config(Fusion::Fused, storage));
    std::vector<Signature> places;
    for (int i = 0; i < 600; ++i) {
      places.push_back(random_signature(Method::ScanContext, rng));
      db.add({0, i}, {places.back()});
    }
    QueryOptions all, refined, everything;
    all.refine = 0;  // every candidate with every version
    refined.refine = 8;
    everything.refine = 1000000;
    int same_best = 0;
    for (int i = 0; i < 600; i += 30) {
      const PlaceDescriptor q{with_versions(places[i], rng)};
      const auto a = db.query(q, 5, all), b = db.query(q, 5, refined),
                 c = db.query(q, 5, everything);
      ASSERT_EQ(a.size(), 5u);
      ASSERT_EQ(b.size(), 5u);
      ASSERT_EQ(c.size(), 5u);
      for (int j = 0; j < 5; ++j) {  // refining everything is scoring everything
        EXPECT_EQ(a[j].index, c[j].index);
        EXPECT_EQ(a[j].distance, c[j].distance);
      }
      for (const Candidate& r : b) {  // k <= refine: every result has its exact distance
        const auto same = std::find_if(a.begin(), a.end(),
                                       [&](const Candidate& x) { return x.index == r.index; });
        if (same != a.end()) {
          EXPECT_EQ(same->distance, r.distance);
        }
      }
      same_best += a[0].index == b[0].index;
      EXPECT_EQ(b[0].index, static_cast<std::size_t>(i));  // the place itself is a version
    }
    EXPECT_EQ(same_best, 20);
  }
}

TEST(CompactDatabase, OnlyScanContextPlacesMayBeCompact) {
  DatabaseConfig c;
  c.method = Method::M2dp;
  c.storage = PlaceStorage::Compact;
  EXPECT_THROW(Database{c}, std::invalid_argument);
  QueryOptions o;
  o.refine = -1;
  Database db;
  std::mt19937 rng(2);
  db.add({0, 0}, {random_signature(Method::ScanContext, rng)});
  EXPECT_THROW(db.query({random_signature(Method::ScanContext, rng)}, 1, o), std::invalid_argument);
}

}  // namespace
}  // namespace loopscan

namespace loopscan {
namespace {

// More rings than the coarse key has dimensions for (they are averaged in groups): indexed
// queries still find a noisy copy of a place.
TEST(CompactDatabase, ManyRingsStillIndex) {
  DatabaseConfig config;
  config.scan_context.rings = 45;
  config.scan_context.sectors = 20;
  Database db(config);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Signature> places;
  for (int i = 0; i < 200; ++i) {
    Signature s(1, 2 * 45 * 20);
    for (Eigen::Index j = 0; j < s.size(); ++j) s(j) = u(rng) < 0.3 ? u(rng) : 0.0;
    places.push_back(s);
    db.add({0, i}, {s});
  }
  for (int i = 0; i < 200; i += 20) {
    Signature q = places[i];
    for (Eigen::Index j = 0; j < q.size(); ++j) q(j) *= 1 + 0.05 * (u(rng) - 0.5);
    const auto got = db.query({q}, 1);
    ASSERT_EQ(got.size(), 1u);
    EXPECT_EQ(got[0].index, static_cast<std::size_t>(i));
  }
}

}  // namespace
}  // namespace loopscan
