// The place database: the KD-tree against brute force, exact and indexed queries against
// difference rows built from the pair distances, query options, and relative yaw.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <thread>

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

TEST(KeyIndex, NearestEqualsBruteForceAmongEligible) {
  for (int dims : {2, 20}) {
    for (std::size_t n : {1u, 7u, 100u, 2000u, 3500u, 5000u}) {  // trees + tail
      std::mt19937 rng(static_cast<unsigned>(dims * 10007 + n));
      std::normal_distribution<float> g;
      const std::size_t stride = dims + 3;
      std::vector<float> data(n * stride);
      for (float& v : data) v = g(rng);
      KeyIndex index(dims);
      for (std::size_t i = 0; i < n; ++i) index.add(&data[i * stride + 1]);
      ASSERT_EQ(index.size(), n);
      const auto eligible = [](std::size_t i) { return i % 3 != 0; };
      for (int trial = 0; trial < 10; ++trial) {
        std::vector<float> key(dims);
        for (float& v : key) v = g(rng);
        std::vector<std::pair<float, std::size_t>> got, want;
        const std::size_t count = trial % 2 ? 5 : 300;  // 300: the result set cuts itself back
        index.nearest(key.data(), count, eligible, got);
        for (std::size_t i = 0; i < n; ++i) {
          if (!eligible(i)) continue;
          float d = 0;
          for (int k = 0; k < dims; ++k) d += std::pow(key[k] - data[i * stride + 1 + k], 2.f);
          want.emplace_back(d, i);
        }
        std::sort(want.begin(), want.end());
        want.resize(std::min<std::size_t>(count, want.size()));
        ASSERT_EQ(got.size(), want.size()) << "dims " << dims << " n " << n;
        for (std::size_t j = 0; j < got.size(); ++j) {
          EXPECT_NEAR(got[j].first, want[j].first, 1e-4f * (1 + want[j].first));
        }
      }
    }
  }
}

// Fused, z-scored oracle row over the eligible places, ranked.
std::vector<std::pair<double, std::size_t>> oracle_ranking(Method m, const Signature& q,
                                                           const std::vector<Signature>& db,
                                                           const std::vector<std::size_t>& ids,
                                                           Fusion fusion) {
  const int C = m == Method::Delight ? 1 : 2;
  Eigen::MatrixXd rows(C, static_cast<Eigen::Index>(ids.size()));
  for (std::size_t j = 0; j < ids.size(); ++j) {
    for (int c = 0; c < C; ++c) rows(c, j) = oracle(m, q, db[ids[j]], Component(c));
  }
  const Eigen::RowVectorXd row = combine_components(rows, C == 1 ? Fusion::Fused : fusion);
  std::vector<std::pair<double, std::size_t>> ranked;
  for (std::size_t j = 0; j < ids.size(); ++j) ranked.emplace_back(row(j), ids[j]);
  std::stable_sort(ranked.begin(), ranked.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  return ranked;
}

TEST(Database, ExactQueriesMatchTheOracleRows) {
  for (Method m : {Method::ScanContext, Method::M2dp, Method::Delight}) {
    for (Fusion fusion : {Fusion::Fused, Fusion::Structure}) {
      for (int n : {1, 2, 13, 60}) {
        std::mt19937 rng(static_cast<unsigned>(n * 3 + static_cast<int>(m)));
        DatabaseConfig cfg;
        cfg.method = m;
        cfg.fusion = fusion;
        Database db(cfg);
        std::vector<Signature> sigs;
        for (int i = 0; i < n; ++i) {
          sigs.push_back(random_signature(m, rng));
          db.add({i % 2, i}, {sigs.back()});
        }
        QueryOptions opt;
        opt.retrieval = Retrieval::Exact;
        opt.exclude_recent = n / 4;
        opt.sessions = n > 2 ? std::vector<int>{0} : std::vector<int>{};
        const Signature q = random_signature(m, rng);
        std::vector<std::size_t> ids;
        for (int i = 0; i < n - n / 4; ++i) {
          if (opt.sessions.empty() || i % 2 == 0) ids.push_back(i);
        }
        const auto want = oracle_ranking(m, q, sigs, ids, fusion);
        const auto got = db.query({q}, 5, opt);
        ASSERT_EQ(got.size(), std::min<std::size_t>(5, want.size()))
            << method_name(m) << " n=" << n;
        for (std::size_t j = 0; j < got.size(); ++j) {
          EXPECT_NEAR(got[j].distance, want[j].first, 2e-4 * (1 + std::abs(want[j].first)))
              << method_name(m) << " n=" << n << " rank " << j;
          EXPECT_EQ(got[j].place.keyframe, static_cast<int>(got[j].index));
          EXPECT_EQ(got[j].place.session, static_cast<int>(got[j].index % 2));
        }
        if (!got.empty()) {
          EXPECT_EQ(got[0].index, want[0].second);
          EXPECT_EQ(std::isnan(got[0].yaw_rad), m != Method::ScanContext);
        }
      }
    }
  }
}

TEST(Database, IndexedEqualsExactWhenTheIndexProposesEverything) {
  for (Method m : {Method::ScanContext, Method::M2dp, Method::Delight}) {
    std::mt19937 rng(77);
    DatabaseConfig cfg;
    cfg.method = m;
    Database db(cfg);
    const int n = 150;
    for (int i = 0; i < n; ++i) db.add({0, i}, {random_signature(m, rng)});
    QueryOptions exact, indexed;
    exact.retrieval = Retrieval::Exact;
    indexed.candidates = indexed.stats_sample = n;
    for (int trial = 0; trial < 5; ++trial) {
      const PlaceDescriptor q{random_signature(m, rng)};
      const auto a = db.query(q, 3, exact), b = db.query(q, 3, indexed);
      ASSERT_EQ(a.size(), b.size());
      for (std::size_t j = 0; j < a.size(); ++j) {
        EXPECT_EQ(a[j].index, b[j].index) << method_name(m);
        EXPECT_DOUBLE_EQ(a[j].distance, b[j].distance);
      }
    }
  }
}

TEST(Database, IndexedFindsANoisyCopyOfAStoredPlace) {
  // Perturbed copies of stored places: the index must hand the original to exact scoring.
  for (Method m : {Method::ScanContext, Method::M2dp, Method::Delight}) {
    std::mt19937 rng(5);
    std::normal_distribution<double> noise(0.0, 0.05);
    DatabaseConfig cfg;
    cfg.method = m;
    Database db(cfg);
    std::vector<Signature> sigs;
    for (int i = 0; i < 400; ++i) {
      sigs.push_back(random_signature(m, rng));
      db.add({0, i}, {sigs.back()});
    }
    int hits = 0;
    for (int i = 0; i < 400; i += 20) {
      Signature q = sigs[i];
      for (Eigen::Index j = 0; j < q.size(); ++j) {
        if (q(j) != 0)
          q(j) = std::max(0.0, q(j) + (m == Method::M2dp ? noise(rng) : 0.5 * noise(rng)));
      }
      const auto got = db.query({q}, 1);
      hits += !got.empty() && got[0].index == static_cast<std::size_t>(i);
    }
    EXPECT_EQ(hits, 20) << method_name(m);
  }
}

TEST(Database, IndexedStatisticsSurviveSparseFilters) {
  // Only every 37th place may match: the strided statistics sample would miss them all.
  std::mt19937 rng(4);
  Database db;
  std::vector<Signature> sigs;
  for (int i = 0; i < 400; ++i) {
    sigs.push_back(random_signature(Method::ScanContext, rng));
    db.add({0, i}, {sigs.back()});
  }
  QueryOptions exact, indexed;
  exact.retrieval = Retrieval::Exact;
  exact.accept = indexed.accept = [](std::size_t i, const PlaceRef&) { return i % 37 == 0; };
  const auto a = db.query({sigs[74]}, 3, exact), b = db.query({sigs[74]}, 3, indexed);
  ASSERT_EQ(a.size(), 3u);
  ASSERT_EQ(b.size(), 3u);
  EXPECT_EQ(a[0].index, 74u);
  EXPECT_EQ(b[0].index, 74u);
  EXPECT_LT(b[0].distance, b[1].distance);          // real z-scores, not all zero
  EXPECT_NEAR(b[0].distance, a[0].distance, 1e-9);  // the sample is all 11 eligible places
}

TEST(Database, ThreadedExactSearchGivesTheSameResults) {
  std::mt19937 rng(8);
  Database db;
  for (int i = 0; i < 600; ++i) db.add({0, i}, {random_signature(Method::ScanContext, rng)});
  QueryOptions one, two;
  one.retrieval = two.retrieval = Retrieval::Exact;
  two.threads = 2;
  const PlaceDescriptor q{random_signature(Method::ScanContext, rng)};
  const auto a = db.query(q, 5, one), b = db.query(q, 5, two);
  ASSERT_EQ(a.size(), 5u);
  ASSERT_EQ(b.size(), 5u);
  for (int j = 0; j < 5; ++j) {
    EXPECT_EQ(a[j].index, b[j].index);
    EXPECT_EQ(a[j].distance, b[j].distance);
  }
}

// query() is const and may run on several threads at once (the background loop closer's
// caller queries while its worker reads the same database): each thread's results are the
// serial ones. Run under ThreadSanitizer by scripts/test-thread-sanitizer.
TEST(Database, ConcurrentQueriesGiveTheSerialResults) {
  std::mt19937 rng(9);
  Database db;
  for (int i = 0; i < 400; ++i) db.add({0, i}, {random_signature(Method::ScanContext, rng)});
  std::vector<PlaceDescriptor> queries;
  for (int i = 0; i < 8; ++i) queries.push_back({random_signature(Method::ScanContext, rng)});
  QueryOptions options;
  options.exclude_recent = 10;
  std::vector<std::vector<Candidate>> serial;
  for (const PlaceDescriptor& q : queries) serial.push_back(db.query(q, 3, options));
  std::vector<std::vector<std::vector<Candidate>>> found(3);
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < found.size(); ++t) {
    threads.emplace_back([&, t] {
      for (const PlaceDescriptor& q : queries) found[t].push_back(db.query(q, 3, options));
    });
  }
  for (std::thread& t : threads) t.join();
  for (const auto& per_thread : found) {
    ASSERT_EQ(per_thread.size(), serial.size());
    for (std::size_t i = 0; i < serial.size(); ++i) {
      ASSERT_EQ(per_thread[i].size(), serial[i].size());
      for (std::size_t j = 0; j < serial[i].size(); ++j) {
        EXPECT_EQ(per_thread[i][j].index, serial[i][j].index);
        EXPECT_EQ(per_thread[i][j].distance, serial[i][j].distance);
      }
    }
  }
}

TEST(Database, OptionsFilterAndTheUniquenessTest) {
  std::mt19937 rng(3);
  Database db;
  const Signature a = random_signature(Method::ScanContext, rng);
  for (int i = 0; i < 30; ++i) {
    db.add({i < 20 ? 0 : 1, i},
           {i == 5 || i == 25 ? a : random_signature(Method::ScanContext, rng)});
  }
  QueryOptions opt;
  opt.retrieval = Retrieval::Exact;
  auto got = db.query({a}, 2, opt);
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(std::set<std::size_t>({got[0].index, got[1].index}), std::set<std::size_t>({5, 25}));
  EXPECT_NEAR(got[0].yaw_rad, 0.0, 1e-6);  // identical signatures, identity frames
  opt.sessions = {1};
  got = db.query({a}, 1, opt);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].index, 25u);
  opt.exclude_recent = 5;  // drops 25..29
  got = db.query({a}, 1, opt);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_NE(got[0].index, 25u);
  opt = {};
  opt.retrieval = Retrieval::Exact;
  opt.max_distance = got[0].distance - 1.0;  // nothing is that close except the copies
  got = db.query({a}, 5, opt);
  EXPECT_EQ(got.size(), 2u);
  // Two equally good distinct places: not unique. Same session and close ids: unique.
  opt = {};
  opt.uniqueness_ratio = 0.8;
  EXPECT_TRUE(db.query({a}, 1, opt).empty());
  opt.sessions = {0};
  EXPECT_EQ(db.query({a}, 1, opt).size(), 1u);
  EXPECT_THROW(db.query({Signature::Zero(1, 10)}, 1), std::invalid_argument);
  EXPECT_THROW(db.add({0, 99}, {Signature::Zero(4, 10)}), std::invalid_argument);
  EXPECT_EQ(db.size(), 30u);
}

double wrap(double a) { return std::remainder(a, 2.0 * M_PI); }

TEST(Database, YawOfARotatedScanIsTheRotation) {
  // The same street seen from a keyframe turned by psi about the camera's up axis (-y).
  const Cloud base = test::street_cloud(9, 4000);
  const DescriptorConfig cfg = DescriptorConfig::for_mode(Mode::Default);
  Database db;
  PlaceDescriptor place;
  place.signature = describe(Method::ScanContext, base, cfg, &place.frame);
  db.add({0, 0}, place);
  const double sector = 2 * M_PI / 60;
  for (double psi : {0.0, 0.3, -0.7, 1.5, 2.9, -2.2}) {
    // A point fixed in the world: p_query = R p_place, with R the inverse of the query's turn.
    const Eigen::Matrix3d R = Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitY()).toRotationMatrix();
    PlaceDescriptor q;
    q.signature =
        describe(Method::ScanContext, test::transformed(base, R, {0.3, 0, -0.4}), cfg, &q.frame);
    const auto got = db.query(q, 1);
    ASSERT_EQ(got.size(), 1u);
    // Forward of the place keyframe (+z) in the query frame is R e_z.
    const Eigen::Vector3d f = R * Eigen::Vector3d::UnitZ();
    const double want = std::atan2(-f.x(), f.z());
    EXPECT_LE(std::abs(wrap(got[0].yaw_rad - want)), sector) << "psi " << psi;
  }
}

TEST(Database, RelativeYawComposesWithTheFrames) {
  // Descriptor axes (up = camera y, then z, x): a shift of s sectors is a turn of s sectors.
  Eigen::Matrix3d B0;
  B0 << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  EXPECT_NEAR(relative_yaw(B0, B0, 0, false, 60), 0.0, 1e-12);
  const double y10 = relative_yaw(B0, B0, 10, false, 60);
  EXPECT_NEAR(std::abs(y10), 10 * 2 * M_PI / 60, 1e-9);
  EXPECT_NEAR(relative_yaw(B0, B0, 50, false, 60), -y10, 1e-9);
  // Both frames turned by the same yaw: the relative yaw does not change.
  const Eigen::Matrix3d B =
      B0 * Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()).toRotationMatrix();
  EXPECT_NEAR(wrap(relative_yaw(B, B, 10, false, 60) - y10), 0.0, 1e-9);
  // Only the place's frame turned by 0.4: the yaw moves by 0.4 one way or the other.
  EXPECT_NEAR(std::abs(wrap(relative_yaw(B0, B, 0, false, 60))), 0.4, 1e-9);
}

}  // namespace
}  // namespace loopscan
