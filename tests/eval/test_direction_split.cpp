// Metrics by direction of the revisit, against a brute-force recount; headings from ground
// truth files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "loopscan/eval/direction_split.hpp"
#include "loopscan/io/ground_truth_files.hpp"
#include "support/test_support.hpp"

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
  const auto dir = test::temp_path("headings");
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

}  // namespace
}  // namespace loopscan::eval
