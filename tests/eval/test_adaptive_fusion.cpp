// Adaptive fusion: weights from the halves' agreement, a leading half chosen by whether its best
// matches follow the drive (brute-force oracle of the sequence reliability), fused rows against
// a direct formula, and on the authors' k06 signatures never below its better half, also when
// one half is made to carry no signal.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "loopscan/core/matching/adaptive_fusion.hpp"
#include "loopscan/core/matching/fusion.hpp"
#include "loopscan/eval/place_evaluation.hpp"
#include "loopscan/io/ground_truth_files.hpp"
#include "loopscan/io/incoming_ids.hpp"
#include "loopscan/io/matrix_text.hpp"
#include "support/test_support.hpp"

namespace loopscan::eval {
namespace {

std::vector<Eigen::RowVectorXd> random_rows(std::mt19937& rng, int n, int m) {
  std::normal_distribution<double> g;
  std::vector<Eigen::RowVectorXd> rows(n, Eigen::RowVectorXd(m));
  for (auto& r : rows) {
    for (int j = 0; j < m; ++j) r[j] = g(rng);
  }
  return rows;
}

FusionWeights weights_of(const std::vector<Eigen::RowVectorXd>& s,
                         const std::vector<Eigen::RowVectorXd>& g, int mask = 0) {
  FusionStatistics a, b;  // two "threads", merged
  for (std::size_t q = 0; q < s.size(); ++q) {
    (q % 2 ? a : b).add_row(s[q], g[q], static_cast<int>(q), mask);
  }
  a.merge(b);
  return a.weights();
}

TEST(AdaptiveFusion, AgreeingHalvesFuseLikeThePaperAContradictingHalfFades) {
  std::mt19937 rng(3);
  const int n = 300, m = 300;
  auto structure = random_rows(rng, n, m);
  for (int q = 0; q < n; ++q) structure[q][(q + 150) % m] -= 6;  // a clear revisit per query
  FusionWeights w = weights_of(structure, structure);
  EXPECT_DOUBLE_EQ(w.agreement, 1.0);
  EXPECT_DOUBLE_EQ(w.structure, 2.0);
  EXPECT_DOUBLE_EQ(w.intensity, 1.0);
  // Intensity that knows nothing: its weight goes to ~0, structure keeps 2.
  const auto noise = random_rows(rng, n, m);
  w = weights_of(structure, noise);
  EXPECT_DOUBLE_EQ(w.structure, 2.0);
  EXPECT_LT(w.intensity, 0.05);
  EXPECT_NEAR(w.chance, 3.0 / m, 1e-12);
  // The other way round: the half without signal (structure, noise) fades.
  w = weights_of(noise, structure);
  EXPECT_DOUBLE_EQ(w.intensity, 1.0);
  EXPECT_LT(w.structure, 0.1);
  // With a mask the chance level counts the allowed places only.
  w = weights_of(structure, structure, 100);
  EXPECT_NEAR(w.chance, 0.0, 0.02);
  EXPECT_EQ(parse_fusion("adaptive"), Fusion::Adaptive);
}

TEST(AdaptiveFusion, FusedRowIsTheMeanOfRowAndGlobalZScoresOracle) {
  std::mt19937 rng(9);
  const int n = 40, m = 25;
  const auto s = random_rows(rng, n, m);
  auto g = random_rows(rng, n, m);  // intensity: structure plus a little noise, so both count
  for (int q = 0; q < n; ++q) g[q] = s[q] + 0.2 * g[q];
  const FusionWeights w = weights_of(s, g);
  ASSERT_GT(w.structure, 0);
  ASSERT_GT(w.intensity, 0);
  // Global statistics by brute force over every entry (n - 1 normaliser).
  auto stats = [&](const std::vector<Eigen::RowVectorXd>& rows, double& mean, double& sd) {
    double sum = 0, cnt = 0;
    for (const auto& r : rows) {
      for (int j = 0; j < m; ++j) sum += r[j], cnt += 1;
    }
    mean = sum / cnt;
    double ss = 0;
    for (const auto& r : rows) {
      for (int j = 0; j < m; ++j) ss += (r[j] - mean) * (r[j] - mean);
    }
    sd = std::sqrt(ss / (cnt - 1));
  };
  double ms, ss, mi, si;
  stats(s, ms, ss);
  stats(g, mi, si);
  EXPECT_NEAR(w.structure_mean, ms, 1e-12);
  EXPECT_NEAR(w.structure_std, ss, 1e-9);
  EXPECT_NEAR(w.intensity_std, si, 1e-9);
  for (int q = 0; q < n; q += 7) {
    const Eigen::RowVectorXd row = adaptive_fused_row(s[q], g[q], w);
    for (int j = 0; j < m; ++j) {
      auto rowz = [&](const Eigen::RowVectorXd& r) {
        const double mean = r.mean();
        const double sd = std::sqrt((r.array() - mean).square().sum() / (m - 1));
        return (r[j] - mean) / sd;
      };
      const double want = 0.5 * (w.structure * (rowz(s[q]) + (s[q][j] - ms) / ss) +
                                 w.intensity * (rowz(g[q]) + (g[q][j] - mi) / si));
      EXPECT_NEAR(row[j], want, 1e-9);
    }
  }
}

// Rows of a drive: query q revisits place (q + n / 2) % m, whose distance dips by `dip` (its
// neighbours by half as much), over unit Gaussian noise.
std::vector<Eigen::RowVectorXd> revisit_rows(std::mt19937& rng, int n, int m, double dip) {
  auto rows = random_rows(rng, n, m);
  for (int q = 0; q < n; ++q) {
    const int t = (q + n / 2) % m;
    rows[q][t] -= dip;
    rows[q][(t + 1) % m] -= dip / 2;
    rows[q][(t + m - 1) % m] -= dip / 2;
  }
  return rows;
}

// Rows that know nothing but stand out more than a real revisit: a few "hub" places are far
// closer than anything else to every query (a descriptor collapsed across seasons).
std::vector<Eigen::RowVectorXd> hub_rows(std::mt19937& rng, int n, int m) {
  auto rows = random_rows(rng, n, m);
  std::normal_distribution<double> jitter(0, 0.5);
  for (auto& r : rows) {
    for (int hub = 0; hub < m; hub += m / 6) r[hub] -= 5 + jitter(rng);
  }
  return rows;
}

// Brute force: consecutive queries' argmins within 5 places, above the share of all pairs of
// queries whose argmins are that close.
double sequence_oracle(const std::vector<Eigen::RowVectorXd>& rows) {
  std::vector<int> best(rows.size());
  for (std::size_t q = 0; q < rows.size(); ++q) rows[q].minCoeff(&best[q]);
  double follow = 0, close = 0, pairs = 0;
  for (std::size_t q = 1; q < best.size(); ++q) follow += std::abs(best[q] - best[q - 1]) <= 5;
  for (std::size_t a = 0; a < best.size(); ++a) {
    for (std::size_t b = a + 1; b < best.size(); ++b) {
      close += std::abs(best[a] - best[b]) <= 5;
      pairs += 1;
    }
  }
  const double chance = close / pairs;
  return (follow / static_cast<double>(best.size() - 1) - chance) / (1 - chance);
}

TEST(AdaptiveFusion, AHalfWithoutSignalNeverLeadsEvenWhenItStandsOutMore) {
  std::mt19937 rng(11);
  const int n = 400, m = 400;
  const auto signal = revisit_rows(rng, n, m, 3.5), hubs = hub_rows(rng, n, m);
  FusionWeights w = weights_of(signal, hubs);
  EXPECT_GT(w.intensity_peak, w.structure_peak);  // the peak alone would follow the hubs
  EXPECT_NEAR(w.structure_sequence, sequence_oracle(signal), 1e-12);
  EXPECT_NEAR(w.intensity_sequence, sequence_oracle(hubs), 1e-12);
  EXPECT_GT(w.structure_sequence, 0.4);
  EXPECT_LT(std::abs(w.intensity_sequence), 0.1);
  EXPECT_DOUBLE_EQ(w.structure, 2.0);
  EXPECT_EQ(w.intensity, 0.0);
  // One half alone ranks exactly like that half.
  for (int q = 0; q < n; q += 37) {
    EXPECT_TRUE(adaptive_fused_row(signal[q], hubs[q], w).cwiseEqual(signal[q]).all());
  }
  w = weights_of(hubs, signal);  // the other way round
  EXPECT_EQ(w.structure, 0.0);
  EXPECT_DOUBLE_EQ(w.intensity, 1.0);
  EXPECT_TRUE(adaptive_fused_row(hubs[5], signal[5], w).cwiseEqual(signal[5]).all());
}

TEST(AdaptiveFusion, WithoutConsecutiveQueriesThePeakDecides) {
  std::mt19937 rng(12);
  const int n = 400, m = 400;
  const auto signal = revisit_rows(rng, n, m, 3.5), hubs = hub_rows(rng, n, m);
  FusionStatistics stats;
  for (int q = 0; q < n; ++q) stats.add_row(signal[q], hubs[q], 2 * q, 0);  // every other query
  const FusionWeights w = stats.weights();
  EXPECT_TRUE(std::isnan(w.structure_sequence));
  EXPECT_TRUE(std::isnan(w.intensity_sequence));
  EXPECT_EQ(w.structure, 0.0);  // nothing tells the hubs apart from a revisit
  EXPECT_DOUBLE_EQ(w.intensity, 1.0);
}

TEST(AdaptiveFusion, FusedHalvesOfTheAuthorsK06SignaturesAreNeverBelowTheBetterHalf) {
  LOOPSCAN_REQUIRE_FIXTURE();
  const std::string d = test::fixture_dir();
  const auto gt = io::read_positions(d + "/gt.txt", io::GtFormat::Kitti);
  std::vector<Eigen::Vector3d> pos;
  for (int id : io::read_incoming_ids(d + "/reference/incoming_id_file.txt")) pos.push_back(gt[id]);
  for (Method method : {Method::ScanContext, Method::M2dp}) {
    const Eigen::MatrixXd all =
        io::read_matrix_text(d + "/reference/signatures_" + method_name(method) + ".txt.gz");
    const int rows = rows_per_place(method), half = static_cast<int>(all.cols()) / 2;
    std::vector<Signature> places;
    for (Eigen::Index r = 0; r < all.rows(); r += rows) places.push_back(all.middleRows(r, rows));
    ASSERT_EQ(places.size(), pos.size());
    // Queries whose structure (then intensity) half is another place's: no signal in that half.
    std::mt19937 rng(4);
    std::vector<int> perm(places.size());
    for (std::size_t i = 0; i < perm.size(); ++i) perm[i] = static_cast<int>(i);
    std::shuffle(perm.begin(), perm.end(), rng);
    auto scrambled = [&](int first_column) {
      std::vector<Signature> out = places;
      for (std::size_t i = 0; i < out.size(); ++i) {
        out[i].middleCols(first_column, half) = places[perm[i]].middleCols(first_column, half);
      }
      return out;
    };
    const std::vector<std::vector<Signature>> query_sets = {places, scrambled(0), scrambled(half)};
    for (std::size_t set = 0; set < query_sets.size(); ++set) {
      auto auc = [&](Fusion fusion) {
        PlaceEvaluationOptions o = PlaceEvaluationOptions::make(method, Mode::Default);
        o.fusion = fusion;
        o.threads = 2;
        return evaluate_places(query_sets[set], places, pos, pos, o).pr;
      };
      const PrResult a = auc(Fusion::Adaptive), s = auc(Fusion::Structure),
                     i = auc(Fusion::Intensity);
      const PrResult& better = s.auc >= i.auc ? s : i;
      SCOPED_TRACE(method_name(method) + " query set " + std::to_string(set));
      if (set == 0) {
        EXPECT_GE(a.auc, better.auc);
        EXPECT_GE(a.recall_at_100_precision, better.recall_at_100_precision);
      } else {  // the half with signal alone, exactly
        EXPECT_EQ(a.auc, better.auc);
        EXPECT_EQ(a.recall_at_100_precision, better.recall_at_100_precision);
        EXPECT_LT((set == 1 ? s : i).auc, 0.2);  // the scrambled half really is noise
      }
    }
  }
}

}  // namespace
}  // namespace loopscan::eval
