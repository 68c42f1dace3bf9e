// Metrics by direction of the revisit, against a brute-force recount; headings from ground
// truth files; adaptive fusion weights.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "loopscan/core/matching/adaptive_fusion.hpp"
#include "loopscan/core/matching/fusion.hpp"
#include "loopscan/eval/direction_split.hpp"
#include "loopscan/io/ground_truth_files.hpp"

namespace loopscan::eval {
namespace {

TEST(DirectionSplit, EqualsABruteForceRecountPerClass) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 60), angle(0, 2 * M_PI), unit(0, 1);
  const int n = 120;
  std::vector<Eigen::Vector3d> pos(n), heading(n);
  for (int i = 0; i < n; ++i) {
    pos[i] = {u(rng), 0, u(rng)};
    const double a = angle(rng);
    heading[i] = {std::cos(a), 0, std::sin(a)};
  }
  std::vector<QueryMatch> matches;
  for (int i = 0; i < n; ++i) matches.push_back({i, int(unit(rng) * n), unit(rng)});
  const Protocol protocol{6.0, 10};
  const PrResult pr = evaluate_matches(matches, pos, pos, protocol);
  const DirectionSplit split = split_by_direction(pr, pos, pos, heading, heading, protocol);
  EXPECT_EQ(split.same.n_loops + split.opposite.n_loops, pr.n_gt_loops);

  for (int cls = 0; cls < 2; ++cls) {
    // Oracle: class of each query from a plain double loop, then the PR walk by hand.
    std::vector<int> loop_class(n, -1);
    int n_loops = 0, top1 = 0;
    for (int i = 0; i < n; ++i) {
      int best = -1;
      for (int j = 0; j < n; ++j) {
        if (std::abs(i - j) < 10) continue;
        if (best < 0 || (pos[i] - pos[j]).norm() < (pos[i] - pos[best]).norm()) best = j;
      }
      if ((pos[i] - pos[best]).norm() >= 6.0) continue;
      loop_class[i] = heading[i].dot(heading[best]) < 0 ? 1 : 0;
      if (loop_class[i] == cls) ++n_loops;
    }
    std::vector<QueryMatch> kept;
    for (const QueryMatch& m : matches) {
      if (loop_class[m.query] == -1 || loop_class[m.query] == cls) kept.push_back(m);
    }
    std::stable_sort(kept.begin(), kept.end(), [](const QueryMatch& a, const QueryMatch& b) {
      return a.distance < b.distance;
    });
    double auc = 0, p_prev = 0, r_prev = 0;
    int tp = 0;
    for (std::size_t k = 0; k < kept.size(); ++k) {
      const bool ok = (pos[kept[k].query] - pos[kept[k].match]).norm() < 6.0;
      tp += ok;
      if (ok && loop_class[kept[k].query] == cls) ++top1;
      const double p = double(tp) / double(k + 1), r = double(tp) / n_loops;
      if (k > 0) auc += (r - r_prev) * (p + p_prev) / 2;
      p_prev = p;
      r_prev = r;
    }
    const DirectionMetrics& d = cls == 0 ? split.same : split.opposite;
    ASSERT_GT(n_loops, 0);
    EXPECT_EQ(d.n_loops, n_loops);
    EXPECT_EQ(d.top1_correct, top1);
    EXPECT_EQ(d.pr.n_queries, static_cast<int>(kept.size()));
    EXPECT_NEAR(d.pr.auc, auc, 1e-12);
  }
  EXPECT_THROW(split_by_direction(pr, pos, pos, {}, heading, protocol), std::invalid_argument);
}

TEST(Headings, KittiCameraAxisAndRobotCarMotion) {
  const auto dir = std::filesystem::temp_directory_path() / "loopscan_headings";
  std::filesystem::create_directories(dir);
  {
    std::ofstream k(dir / "kitti.txt");  // camera turned 90 deg about y: z axis = world +x
    k << "0 0 1 0 0 1 0 0 -1 0 0 0\n1 0 0 0 0 1 0 0 0 0 1 5\n";
    std::ofstream r(dir / "robotcar.txt");  // driving north-east
    for (int i = 0; i < 10; ++i) r << i << ' ' << i << " 0\n";
  }
  const auto k = io::read_headings((dir / "kitti.txt").string(), io::GtFormat::Kitti);
  ASSERT_EQ(k.size(), 2u);
  EXPECT_TRUE(k[0].isApprox(Eigen::Vector3d(1, 0, 0)));
  EXPECT_TRUE(k[1].isApprox(Eigen::Vector3d(0, 0, 1)));
  const auto r = io::read_headings((dir / "robotcar.txt").string(), io::GtFormat::RobotCar);
  ASSERT_EQ(r.size(), 10u);
  for (const auto& h : r) EXPECT_TRUE(h.isApprox(Eigen::Vector3d(1, 1, 0).normalized()));
  std::filesystem::remove_all(dir);
}

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
  // The other way round: the less peaked half (structure, noise) fades.
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
  const auto s = random_rows(rng, n, m), g = random_rows(rng, n, m);
  const FusionWeights w = weights_of(s, g);
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

}  // namespace
}  // namespace loopscan::eval
