// Stereo rendering of the synthetic world.
#include <gtest/gtest.h>

#include "support/rendered_street.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "loopscan/sim/renderer.hpp"
#include "loopscan/sim/trajectory.hpp"

namespace loopscan {
namespace {

const test::ShortStreet& street() {
  static const test::ShortStreet s(0.25);
  return s;
}

TEST(Render, ScaledCameraKeepsTheGeometry) {
  const sim::StereoCamera full, half = sim::scaled_camera(full, 0.5);
  EXPECT_EQ(half.width, 621);
  EXPECT_EQ(half.height, 188);
  EXPECT_NEAR(half.baseline(), full.baseline(), 1e-12);
  // The same camera-frame point lands on the same place of the image.
  const Eigen::Vector3d p(1.3, -0.4, 12.0);
  Eigen::Vector2d a, b;
  ASSERT_TRUE(full.project(p, a));
  ASSERT_TRUE(half.project(p, b));
  EXPECT_NEAR((b.x() + 0.5) / half.width, (a.x() + 0.5) / full.width, 1e-3);
  EXPECT_NEAR((b.y() + 0.5) / half.height, (a.y() + 0.5) / full.height, 1e-3);
}

TEST(Render, DeterministicAndIndependentOfThreads) {
  const test::ShortStreet& s = street();
  sim::RenderConfig one, two;
  two.threads = 2;
  const auto& T = s.route.T_world_cam[30];
  const sim::GrayImage a = sim::render_view(s.world, s.conditions, s.camera, T, 0, 30, one);
  const sim::GrayImage b = sim::render_view(s.world, s.conditions, s.camera, T, 0, 30, two);
  EXPECT_EQ(a.pixels, b.pixels);
  const sim::GrayImage c = sim::render_view(s.world, s.conditions, s.camera, T, 0, 31, one);
  EXPECT_NE(a.pixels, c.pixels);  // another frame: other sensor noise
  // Textured enough for a VO: a good share of strong horizontal gradients.
  int strong = 0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 1; x < a.width; ++x) strong += std::abs(a.at(x, y) - a.at(x - 1, y)) > 12;
  }
  EXPECT_GT(strong, a.width * a.height / 50);
}

TEST(Render, RightImageIsTheLeftShiftedByTheDisparity) {
  // For pixels of the left image that see a surface at depth z, the right image shows the same
  // gray bf / z pixels to the left; a wrong disparity matches much worse.
  const test::ShortStreet& s = street();
  sim::RenderConfig rc;
  rc.noise_sigma = 0;
  const auto& T = s.route.T_world_cam[60];
  const sim::GrayImage L = sim::render_view(s.world, s.conditions, s.camera, T, 0, 60, rc);
  const sim::GrayImage R = sim::render_view(s.world, s.conditions, s.camera, T, 1, 60, rc);
  std::vector<double> right, wrong;
  for (int v = 0; v < L.height; v += 2) {
    for (int u = 0; u < L.width; u += 2) {
      const Eigen::Vector3d ray = s.camera.ray(u, v);
      const auto hit = s.world.raycast(T.translation(), T.linear() * ray, 150.0, s.conditions);
      if (!hit) continue;
      const double z = (T.inverse() * hit->point).z();
      const int d = static_cast<int>(std::lround(s.camera.bf / z));
      if (u - d - 3 < 0) continue;
      right.push_back(std::abs(L.at(u, v) - R.at(u - d, v)));
      wrong.push_back(std::abs(L.at(u, v) - R.at(u - d - 3, v)));
    }
  }
  ASSERT_GT(right.size(), 200u);
  auto mean = [](const std::vector<double>& x) {
    double sum = 0;
    for (double v : x) sum += v;
    return sum / x.size();
  };
  EXPECT_LT(mean(right), 0.5 * mean(wrong)) << mean(right) << " vs " << mean(wrong);
  EXPECT_LT(mean(right), 6.0);
}

}  // namespace
}  // namespace loopscan
