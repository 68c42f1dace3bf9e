// The bird's-eye search against a brute-force scorer of every (yaw, shift), and its poses on
// street scenes seen the other way round and metres along the street from the guess; the core
// bird's-eye place's pose in the closer's convention.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "loopscan/closure/birds_eye.hpp"
#include "loopscan/closure/verification.hpp"
#include "loopscan/core/matching/birds_eye_match.hpp"
#include "scene_points.hpp"

namespace loopscan {
namespace {

using closure::Points3f;

double yaw_deg(const Eigen::Isometry3d& T) { return closure::yaw_of(T) * 180 / M_PI; }

double yaw_difference_deg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return std::abs(std::remainder(yaw_deg(a) - yaw_deg(b), 360.0));
}

// The scene as the query sees it (identity) and as a place seen from T^-1 (T_query_place = T),
// independent samples, voxelised.
std::pair<closure::PlaceCloud, closure::PlaceCloud> query_and_place(unsigned seed,
                                                                    const Eigen::Isometry3d& T) {
  const Points3f all = test::street_scene(seed);
  Points3f a, b;
  for (std::size_t i = 0; i < all.size(); ++i) (i % 2 ? b : a).push_back(all[i]);
  const auto place_cloud = [](const Points3f& p) {
    return closure::to_place_cloud(closure::TargetCloud(closure::voxel_cloud(p)));
  };
  return {place_cloud(test::transformed(a, Eigen::Isometry3d::Identity(), 0.03, seed + 1)),
          place_cloud(test::transformed(b, T.inverse(), 0.03, seed + 2))};
}

TEST(BirdsEye, BestPoseScoresTheBruteForceMaximum) {
  closure::BirdsEyeConfig config;
  config.peaks = 1;
  config.yaw_window_deg = 9;
  config.max_shift_m = 5;
  const Eigen::Isometry3d T = closure::yaw_rotation(0.1) * Eigen::Translation3d(1, 0, 3);
  const auto [query_cloud, place] = query_and_place(3, T);
  const closure::BirdsEyeGrid grid(query_cloud, config);
  const Eigen::Isometry3d guess = closure::yaw_rotation(3.0);
  const std::vector<closure::BirdsEyePose> found = closure::birds_eye_search(grid, place, {guess});
  ASSERT_EQ(found.size(), 1u);
  // Every yaw and whole-cell shift, each place point looked up one by one.
  double best = -1;
  Eigen::Isometry3d best_T = Eigen::Isometry3d::Identity();
  const int s = int(std::ceil(config.max_shift_m / config.cell_m));
  for (int k = -3; k <= 3; ++k) {
    const Eigen::Isometry3d Tk = closure::yaw_rotation(k * config.yaw_step_deg * M_PI / 180) * guess;
    std::map<std::pair<int, int>, int> count;
    for (std::size_t i = 0; i < place.structure; ++i) {
      const Eigen::Vector3f& p = place.points[i];
      if (std::hypot(p.x(), p.z()) > config.max_range_m) continue;
      const Eigen::Vector3f q = Tk.cast<float>() * p;
      const Eigen::Vector2i c = grid.cell(q.x(), q.z());
      ++count[{c.x(), c.y()}];
    }
    for (int dr = -s; dr <= s; ++dr) {
      for (int dc = -s; dc <= s; ++dc) {
        double score = 0;
        for (const auto& [c, n] : count) {
          const int r = c.first + dr, col = c.second + dc;
          if (r < 0 || col < 0 || r >= grid.size() || col >= grid.size()) continue;
          score += std::sqrt(double(n)) * grid.at(r, col);
        }
        if (score > best) {
          best = score;
          best_T = Tk;
          best_T.translation() += Eigen::Vector3d(dc * config.cell_m, 0, dr * config.cell_m);
        }
      }
    }
  }
  EXPECT_NEAR(found[0].score, best, 1e-4 * best);
  // The search's pose is the brute force's, moved by at most half a cell (the sub-cell vertex).
  EXPECT_LE((found[0].T_query_place.translation() - best_T.translation()).norm(),
            0.5 * std::sqrt(2.0) * config.cell_m + 1e-9);
  EXPECT_LT(yaw_difference_deg(found[0].T_query_place, best_T), 1e-6);
}

TEST(BirdsEye, FindsPlacesDrivenTheOtherWayMetresAlongTheStreet) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 10; ++trial) {
    SCOPED_TRACE(trial);
    // The other driving direction, up to 7 m along and 2.5 m across the street from the guess
    // (within verification's 8 m).
    const Eigen::Isometry3d T = Eigen::Translation3d(2.5 * u(rng), 0.2 * u(rng), 7 * u(rng)) *
                                closure::yaw_rotation(M_PI + 15 * M_PI / 180 * u(rng));
    const auto [query_cloud, place] = query_and_place(200 + unsigned(trial), T);
    const closure::BirdsEyeGrid grid(query_cloud);
    const std::vector<closure::BirdsEyePose> found =
        closure::birds_eye_search(grid, place, {closure::yaw_rotation(M_PI)});
    ASSERT_FALSE(found.empty());
    EXPECT_LT((found[0].T_query_place.translation() - T.translation()).head<3>().norm(), 1.0);
    EXPECT_LT(yaw_difference_deg(found[0].T_query_place, T), 3.0);
    // And verification seeded by it recovers the pose exactly.
    const closure::TargetCloud target(query_cloud.points);
    const closure::Loop loop =
        closure::verify_candidate(target, place, {closure::yaw_rotation(M_PI)}, {}, &grid);
    EXPECT_EQ(loop.verdict, closure::Verdict::Accepted) << closure::to_string(loop.verdict);
    EXPECT_LT((loop.T_query_match.translation() - T.translation()).norm(), 0.05);
  }
}

TEST(BirdsEye, PlaceWithoutStructureInRangeGivesNoPose) {
  closure::PlaceCloud query;
  query.points = {Eigen::Vector3f(1, 0, 1)};
  query.structure = 1;
  const closure::BirdsEyeGrid grid(query);
  closure::PlaceCloud far;
  far.points = {Eigen::Vector3f(0, 0, 500), Eigen::Vector3f(0, 1.6f, 2)};
  far.structure = 1;  // the second point is ground
  EXPECT_TRUE(closure::birds_eye_search(grid, far, {Eigen::Isometry3d::Identity()}).empty());
}

// The bird's-eye place (core) finds the same pose of a place driven the other way as the
// closer's convention states it: its (x, z, yaw) seeds an alignment as it is.
TEST(BirdsEye, PlacePoseOfTheCoreDescriptorIsTheClosersPose) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const BirdsEyePlaceConfig config;
  auto describe = [&](const closure::PlaceCloud& c) {
    std::vector<float> x, y, z;
    for (const Eigen::Vector3f& p : c.points) x.push_back(p.x()), y.push_back(p.y()), z.push_back(p.z());
    return describe_birds_eye(x.data(), y.data(), z.data(), x.size(), config);
  };
  for (int trial = 0; trial < 5; ++trial) {
    SCOPED_TRACE(trial);
    const Eigen::Isometry3d T = Eigen::Translation3d(2.5 * u(rng), 0.0, 7 * u(rng)) *
                                closure::yaw_rotation(M_PI + 15 * M_PI / 180 * u(rng));
    const auto [query_cloud, place_cloud] = query_and_place(300 + unsigned(trial), T);
    const BirdsEyePlace query = describe(query_cloud), place = describe(place_cloud);
    const BirdsEyePose pose =
        birds_eye_pose(query, place, match_keys(query, place, config.angles).yaw_rad, config);
    const Eigen::Isometry3d found = Eigen::Translation3d(pose.x_m, 0.0, pose.z_m) *
                                    closure::yaw_rotation(pose.yaw_rad);
    EXPECT_LT(yaw_difference_deg(found, T), 6.0);
    EXPECT_LT((found.translation() - T.translation()).norm(), 1.0);
  }
}

TEST(BirdsEye, ConfigRangesAreChecked) {
  closure::BirdsEyeConfig c;
  c.cell_m = 0;
  EXPECT_THROW(closure::validate(c), std::invalid_argument);
  c = {};
  c.peaks = 0;
  EXPECT_THROW(closure::validate(c), std::invalid_argument);
  c = {};
  c.max_range_m = 200;
  c.cell_m = 0.1;
  EXPECT_THROW(closure::validate(c), std::invalid_argument);
}

}  // namespace
}  // namespace loopscan
