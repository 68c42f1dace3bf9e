// GIST: a constant image has no energy; gratings select the filter of their orientation and
// scale; the filter bank peaks where declared.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "support/rendered_street.hpp"

#include "loopscan/baselines/gist.hpp"
#include "loopscan/baselines/inverted_index.hpp"
#include "loopscan/baselines/orb_features.hpp"
#include "loopscan/baselines/vocabulary.hpp"
#include "loopscan/baselines/vocabulary_io.hpp"
#include "loopscan/io/errors.hpp"
#include "loopscan/sim/renderer.hpp"
#include "loopscan/sim/trajectory.hpp"
namespace loopscan {
namespace {

namespace fs = std::filesystem;
using baselines::BowVector;

TEST(Gist, ConstantImageHasNoEnergy) {
  baselines::GistExtractor gist;
  const Eigen::VectorXf d = gist.describe(cv::Mat(200, 300, CV_8UC1, cv::Scalar(117)));
  ASSERT_EQ(d.size(), 512);
  EXPECT_LT(d.cwiseAbs().maxCoeff(), 1e-4f);
}

cv::Mat grating(double frequency, double angle_rad) {
  cv::Mat m(256, 256, CV_8UC1);
  const double fx = frequency * std::cos(angle_rad), fy = frequency * std::sin(angle_rad);
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x)
      m.at<std::uint8_t>(y, x) =
          cv::saturate_cast<std::uint8_t>(128 + 100 * std::cos(2 * M_PI * (fx * x + fy * y)));
  return m;
}

// Filter with the most energy, summed over the grid.
std::pair<int, int> strongest_filter(const Eigen::VectorXf& d, const baselines::GistConfig& c) {
  int best = 0;
  float best_e = -1;
  const int cells = c.grid * c.grid;
  for (int k = 0; k < c.scales * c.orientations; ++k) {
    const float e = d.segment(k * cells, cells).sum();
    if (e > best_e) {
      best_e = e;
      best = k;
    }
  }
  return {best / c.orientations, best % c.orientations};
}

TEST(Gist, GratingsSelectTheFilterOfTheirOrientationAndScale) {
  baselines::GistExtractor gist;
  const baselines::GistConfig& c = gist.config();
  const double step = M_PI / c.orientations;
  for (int s = 0; s < 3; ++s) {
    const double f = 0.3 / std::pow(1.85, s);
    for (int o = 0; o < c.orientations; ++o) {
      // Filter o peaks at angle -o * step in the frequency plane (either lobe of the grating).
      const auto [scale, orientation] = strongest_filter(gist.describe(grating(f, -o * step)), c);
      EXPECT_EQ(scale, s) << "scale " << s << " orientation " << o;
      EXPECT_EQ(orientation, o) << "scale " << s << " orientation " << o;
    }
  }
  // Rotating a grating by 45 degrees moves the response by two orientations; dividing its
  // frequency by 1.85 moves it one scale coarser.
  const auto a = strongest_filter(gist.describe(grating(0.162, -0.35)), c);
  const auto b = strongest_filter(gist.describe(grating(0.162, -0.35 - M_PI / 4)), c);
  const auto coarser = strongest_filter(gist.describe(grating(0.162 / 1.85, -0.35)), c);
  EXPECT_EQ(b.second, (a.second + 2) % c.orientations);
  EXPECT_EQ(coarser.first, a.first + 1);
  EXPECT_EQ(coarser.second, a.second);
}

TEST(Gist, FilterBankPeaksWhereDeclared) {
  baselines::GistConfig c;
  const int n = c.image_size + 2 * c.boundary;
  for (const baselines::GaborFilter& g : baselines::gabor_bank(c)) {
    const auto it = std::max_element(g.transfer.begin(), g.transfer.end());
    const int i = static_cast<int>(it - g.transfer.begin());
    auto freq = [n](int k) { return (k < n / 2 ? k : k - n) / static_cast<double>(n); };
    const double fx = freq(i % n), fy = freq(i / n);
    EXPECT_NEAR(std::hypot(fx, fy), g.peak_cycles_per_pixel, 1.5 / n)
        << g.scale << " " << g.orientation;
    double da = std::atan2(fy, fx) - g.angle_rad;
    da = std::remainder(da, 2 * M_PI);
    EXPECT_LT(std::abs(da), 0.15) << g.scale << " " << g.orientation;
    EXPECT_NEAR(*it, 1.0f, 0.05f);
  }
}

// ---- Bag of Words --------------------------------------------------------------------------

}  // namespace
}  // namespace loopscan
