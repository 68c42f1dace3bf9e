// The VO-output simulator: determinism, density, stereo noise model, visibility, seasons.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "loopscan/sim/vo_simulator.hpp"

namespace loopscan {
namespace {

struct ShortDrive {
  sim::Trajectory route = sim::make_builtin_trajectory("short");
  std::vector<int> keyframes = sim::select_keyframes(route);
  sim::World world = sim::World::build(route.centres(), sim::WorldConfig{});
  sim::StereoCamera camera;
};

const ShortDrive& drive() {
  static const ShortDrive d;
  return d;
}

sim::VoOutput simulate(sim::Season season, unsigned seed, const sim::VoSimConfig& base = {}) {
  const ShortDrive& d = drive();
  sim::VoSimConfig c = base;
  c.seed = seed;
  return sim::simulate_vo(d.route, d.keyframes, d.world, sim::Conditions::for_season(season),
                          d.camera, c);
}

TEST(SimVo, SameSeedSameOutputDifferentSeedDifferent) {
  const sim::VoOutput a = simulate(sim::Season::Summer, 3), b = simulate(sim::Season::Summer, 3);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    ASSERT_EQ(a.points[i].p_world, b.points[i].p_world);
    ASSERT_EQ(a.points[i].intensity, b.points[i].intensity);
  }
  const sim::VoOutput c = simulate(sim::Season::Summer, 4);
  EXPECT_NE(c.points[10].p_world, a.points[10].p_world);
}

TEST(SimVo, DsoLikeDensityAndSortedIds) {
  const sim::VoOutput a = simulate(sim::Season::Summer, 1);
  EXPECT_EQ(a.poses.size(), drive().keyframes.size());
  EXPECT_GT(a.mean_points_per_keyframe, 150.0);  // a few hundred per keyframe
  EXPECT_LE(a.mean_points_per_keyframe, 300.0);
  for (std::size_t i = 1; i < a.points.size(); ++i) ASSERT_LE(a.points[i - 1].id, a.points[i].id);
  for (const IdPoint& p : a.points) {
    ASSERT_GE(p.intensity, 0.f);
    ASSERT_LE(p.intensity, 255.f);
  }
}

TEST(SimVo, StereoDepthNoiseGrowsWithDepthSquared) {
  std::mt19937 rng(5);
  std::normal_distribution<double> n01(0.0, 1.0);
  const double bf = 386.1448, sigma = 0.5;
  for (double z : {5.0, 10.0, 20.0}) {
    double sum = 0, sum2 = 0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
      const double d = sim::noisy_stereo_depth(z, bf, sigma, n01(rng));
      sum += d;
      sum2 += d * d;
    }
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    EXPECT_NEAR(sd, z * z / bf * sigma, 0.05 * z * z / bf * sigma) << "depth " << z;
  }
}

TEST(SimVo, EveryPointIsInFrontOfItsCameraAndInsideTheImage) {
  const sim::VoOutput a = simulate(sim::Season::Fall, 2);
  const sim::StereoCamera& cam = drive().camera;
  std::size_t next = 0;
  for (const KeyframePose& k : a.poses) {
    for (; next < a.points.size() && a.points[next].id == k.id; ++next) {
      const Eigen::Vector3d p_cam =
          k.T_cam_world.leftCols<3>() * a.points[next].p_world + k.T_cam_world.col(3);
      Eigen::Vector2d px;
      ASSERT_GT(p_cam.z(), 0.0);
      ASSERT_TRUE(cam.project(p_cam, px)) << "point " << next << " of keyframe " << k.id;
      ASSERT_LE(p_cam.z(), 45.0 + 1e-6);  // max_depth_m
    }
  }
  EXPECT_EQ(next, a.points.size());
}

TEST(SimVo, WithoutNoiseOrDriftPointsLieOnTheWorldSurfaces) {
  sim::VoSimConfig c;
  c.disparity_sigma_px = 0;
  c.drift_translation_per_m = c.drift_rotation_deg_per_m = 0;
  const sim::VoOutput a = simulate(sim::Season::Summer, 6, c);
  const ShortDrive& d = drive();
  const sim::Conditions summer = sim::Conditions::for_season(sim::Season::Summer);
  // VO frame = world frame of the first keyframe; map back to the simulator's world.
  const Eigen::Isometry3d T_world_vo = d.route.T_world_cam[d.keyframes.front()];
  int checked = 0;
  for (std::size_t i = 0; i < a.points.size(); i += 97) {
    const Eigen::Vector3d p = T_world_vo * a.points[i].p_world;
    const Eigen::Vector3d origin = d.route.T_world_cam[a.points[i].id].translation();
    const Eigen::Vector3d dir = (p - origin).normalized();
    const auto hit = d.world.raycast(origin, dir, 100.0, summer);
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(hit->distance, (p - origin).norm(), 1e-3);
    ++checked;
  }
  EXPECT_GT(checked, 10);
}

TEST(SimVo, WinterKeepsPosesButChangesAppearance) {
  const sim::VoOutput s = simulate(sim::Season::Summer, 9), w = simulate(sim::Season::Winter, 9);
  ASSERT_EQ(s.poses.size(), w.poses.size());
  for (std::size_t k = 0; k < s.poses.size(); ++k) {
    ASSERT_TRUE(s.poses[k].T_cam_world.isApprox(w.poses[k].T_cam_world));
  }
  double gs = 0, gw = 0;
  for (const IdPoint& p : s.points) gs += p.intensity;
  for (const IdPoint& p : w.points) gw += p.intensity;
  EXPECT_GT(std::abs(gs / s.points.size() - gw / w.points.size()), 1.0);
}

}  // namespace
}  // namespace loopscan
