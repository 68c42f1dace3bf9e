// Parts of the stereo VO against known answers: the sparse stereo matcher, corner bucketing
// and windowed bundle adjustment.
#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "support/rendered_street.hpp"

#include "loopscan/eval/odometry_metrics.hpp"
#include "loopscan/sim/renderer.hpp"
#include "loopscan/sim/trajectory.hpp"
#include "loopscan/sim/world.hpp"
#include "loopscan/vo/image_points.hpp"
#include "loopscan/vo/stereo_vo.hpp"
namespace loopscan {
namespace {

cv::Mat random_texture(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> gray(0, 255);
  cv::Mat m(h, w, CV_8UC1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) m.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(gray(rng));
  return m;
}

// A calibration with an absurd baseline asks for disparities of 1e18 px: the search range is
// clamped to the image width (no int overflow), and StereoVo refuses such a camera outright.
TEST(StereoMatch, AbsurdDisparityRangesAreClampedAndAbsurdCamerasRefused) {
  const cv::Mat left = random_texture(200, 40, 3);
  cv::Mat right(left.size(), CV_8UC1, cv::Scalar(0));
  left.colRange(17, left.cols).copyTo(right.colRange(0, left.cols - 17));
  for (const vo::StereoSearch s : {vo::StereoSearch{1, 1e18, 2, 0.85, true},
                                   vo::StereoSearch{1, std::numeric_limits<double>::infinity()},
                                   vo::StereoSearch{std::nan(""), 80}}) {
    const double d = vo::match_disparity(left, right, 150, 20, s);
    EXPECT_TRUE(std::isnan(d) || std::abs(d - 17) < 0.25) << d;
  }
  vo::StereoIntrinsics wide;
  wide.baseline_m = 5e8;  // P1: fx 7e-7, -fx b = -386: what a mutated calib.txt implied
  EXPECT_THROW(vo::StereoVo{wide}, std::invalid_argument);
  vo::StereoIntrinsics tiny_focal;
  tiny_focal.fx = 1e-300;
  EXPECT_THROW(vo::StereoVo{tiny_focal}, std::invalid_argument);
}

TEST(StereoMatch, RecoversAKnownShiftAndRejectsFlatImages) {
  const cv::Mat left = random_texture(200, 40, 3);
  for (int shift : {4, 17, 60}) {
    cv::Mat right(left.size(), CV_8UC1, cv::Scalar(0));
    // right(x) = left(x + shift): a point at left x appears at x - shift in the right image.
    left.colRange(shift, left.cols).copyTo(right.colRange(0, left.cols - shift));
    vo::StereoSearch s{1, 80, 2, 0.85, true};
    for (int x = 100; x < 190; x += 7) {
      const double d = vo::match_disparity(left, right, x, 20, s);
      EXPECT_NEAR(d, shift, 0.25) << "x " << x << " shift " << shift;
    }
  }
  const cv::Mat flat(40, 200, CV_8UC1, cv::Scalar(90));
  EXPECT_FALSE(std::isfinite(vo::match_disparity(flat, flat, 100, 20, {1, 80, 2, 0.85, false})));
  // Window leaving the image.
  EXPECT_FALSE(std::isfinite(vo::match_disparity(left, left, 1, 20, {1, 80, 2, 0.85, false})));
}

// The straightforward matcher: every disparity, every window pixel; `direction` -1 searches
// R leftwards of x (left into right image), +1 rightwards (the left-right check's way back).
double naive_disparity(const cv::Mat& L, const cv::Mat& R, int x, int y, int d_lo, int d_hi, int h,
                       double uniqueness, int direction = -1) {
  std::vector<int> cost;
  std::vector<int> ds;
  for (int d = std::max(d_lo, 0); d <= d_hi; ++d) {
    const int xo = x + direction * d;
    if (xo - h < 0 || xo + h >= R.cols) break;
    int s = 0;
    for (int dy = -h; dy <= h; ++dy)
      for (int dx = -h; dx <= h; ++dx)
        s += std::abs(L.at<std::uint8_t>(y + dy, x + dx) - R.at<std::uint8_t>(y + dy, xo + dx));
    cost.push_back(s);
    ds.push_back(d);
  }
  const int n = static_cast<int>(cost.size());
  if (n < 3) return NAN;
  const int best = static_cast<int>(std::min_element(cost.begin(), cost.end()) - cost.begin());
  int second = INT_MAX;
  for (int i = 0; i < n; ++i)
    if (std::abs(i - best) > 1) second = std::min(second, cost[i]);
  if (best == 0 || best == n - 1 || second == 0 || cost[best] >= uniqueness * second) return NAN;
  const double slope = std::max(cost[best - 1], cost[best + 1]) - cost[best];
  return ds[best] + (slope > 0 ? 0.5 * (cost[best - 1] - cost[best + 1]) / slope : 0.0);
}

TEST(StereoMatch, EqualsTheStraightforwardSearch) {
  const cv::Mat left = random_texture(160, 30, 8);
  cv::Mat right = random_texture(160, 30, 9);
  left.colRange(20, 160).copyTo(right.colRange(0, 140));  // mostly a 20 px shift, some noise
  std::mt19937 rng(2);
  int compared = 0, finite = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int x = 3 + static_cast<int>(rng() % 154), y = 3 + static_cast<int>(rng() % 24);
    const int h = 1 + static_cast<int>(rng() % 3);
    const int d_lo = static_cast<int>(rng() % 10), d_hi = d_lo + 3 + static_cast<int>(rng() % 60);
    if (y - h < 0 || y + h >= 30 || x + h >= 160) continue;
    const double fast =
        vo::match_disparity(left, right, x, y, {double(d_lo), double(d_hi), h, 0.9, false});
    const double slow = naive_disparity(left, right, x, y, d_lo, d_hi, h, 0.9);
    ++compared;
    ASSERT_EQ(std::isfinite(fast), std::isfinite(slow))
        << x << " " << y << " " << h << " " << d_lo << " " << d_hi;
    if (std::isfinite(fast)) {
      ++finite;
      EXPECT_NEAR(
          fast, std::clamp(slow, std::floor(slow + 0.5) - 0.5, std::floor(slow + 0.5) + 0.5), 1e-9);
    }
  }
  EXPECT_GT(compared, 300);
  EXPECT_GT(finite, 50);
}

// The vectorised 16-bit search (half windows up to 7; 8 takes the 32-bit path) against the
// straightforward one on KITTI-wide disparity ranges, with the left-right check (the search
// back rightwards). LOOPSCAN_NO_AVX2=1 runs the baseline kernel.
TEST(StereoMatch, EqualsTheStraightforwardSearchOnWideRangesBothWays) {
  const cv::Mat left = random_texture(700, 40, 10);
  cv::Mat right = random_texture(700, 40, 11);
  left.colRange(37, 700).copyTo(right.colRange(0, 663));
  std::mt19937 rng(5);
  int compared = 0, finite = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const int h = 1 + static_cast<int>(rng() % 8);
    const int x = h + static_cast<int>(rng() % (700 - 2 * h));
    const int y = h + static_cast<int>(rng() % (40 - 2 * h));
    const int d_lo = static_cast<int>(rng() % 40), d_hi = d_lo + 2 + static_cast<int>(rng() % 400);
    const double fast =
        vo::match_disparity(left, right, x, y, {double(d_lo), double(d_hi), h, 0.95, true});
    double slow = naive_disparity(left, right, x, y, d_lo, d_hi, h, 0.95);
    if (std::isfinite(slow)) {
      const double d = std::clamp(slow, std::floor(slow + 0.5) - 0.5, std::floor(slow + 0.5) + 0.5);
      const int xr = static_cast<int>(std::lround(x - d));
      const double back = naive_disparity(right, left, xr, y, d_lo, d_hi, h, 0.95, +1);
      slow = std::isfinite(back) && std::abs(std::clamp(back, std::floor(back + 0.5) - 0.5,
                                                        std::floor(back + 0.5) + 0.5) -
                                             d) <= 1.0
                 ? d
                 : NAN;
    }
    ++compared;
    ASSERT_EQ(std::isfinite(fast), std::isfinite(slow))
        << x << " " << y << " " << h << " " << d_lo << " " << d_hi;
    if (std::isfinite(fast)) {
      ++finite;
      EXPECT_NEAR(fast, slow, 1e-9);
    }
  }
  EXPECT_EQ(compared, 300);
  EXPECT_GT(finite, 100);
}

TEST(StereoMatch, SubPixelShiftOfASmoothTexture) {
  // A smooth pattern sampled at x and at x + 10.4: the parabola fit lands within 0.2 px.
  auto pattern = [](double x, double y) {
    return 128 + 60 * std::sin(0.37 * x + 0.2 * y) + 40 * std::cos(0.11 * x * 1.3 - 0.5 * y);
  };
  cv::Mat left(40, 220, CV_8UC1), right(40, 220, CV_8UC1);
  for (int y = 0; y < 40; ++y) {
    for (int x = 0; x < 220; ++x) {
      left.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(pattern(x, y));
      right.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(pattern(x + 10.4, y));
    }
  }
  int found = 0;
  for (int x = 60; x < 200; x += 5) {
    const double d = vo::match_disparity(left, right, x, 20, {2, 40, 3, 0.95, false});
    if (!std::isfinite(d)) continue;
    ++found;
    EXPECT_NEAR(d, 10.4, 0.2) << x;
  }
  EXPECT_GT(found, 20);
}

TEST(Corners, AtMostOnePerFreeCell) {
  const cv::Mat image = random_texture(400, 120, 5);
  vo::VoConfig config;
  config.grid_cols = 10;
  config.grid_rows = 4;
  const std::vector<cv::Point2f> occupied = {{15, 15}, {390, 110}};
  const std::vector<cv::Point2f> corners = vo::detect_grid_corners(image, occupied, config);
  std::set<int> cells;
  for (const cv::Point2f& p : corners) {
    const int cell = static_cast<int>(p.y / 30) * 10 + static_cast<int>(p.x / 40);
    EXPECT_TRUE(cells.insert(cell).second) << "two corners in cell " << cell;
    EXPECT_NE(cell, 0);
    EXPECT_NE(cell, 39);
  }
  EXPECT_GE(corners.size(), 30u);  // random texture: nearly every free cell has a corner
}

// Patterns with a known answer: a pattern repeated along a direction (bars 10 px apart, rows
// of one gray) is self-similar along it and not across it where each row or column differs;
// random texture nowhere; a flat image everywhere.
TEST(Corners, SelfSimilarAlongALineOnlyWhereThePatternRepeats) {
  const cv::Mat noise = random_texture(200, 120, 9);
  cv::Mat bars(120, 200, CV_8UC1), rows(120, 200, CV_8UC1);
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 200; ++x) {
      // Posts every 10 px whose brightness varies row by row, as a rail's posts down the image.
      const int row_gray = noise.at<std::uint8_t>(y, 0);
      bars.at<std::uint8_t>(y, x) =
          static_cast<std::uint8_t>(x % 10 < 3 ? row_gray : 255 - row_gray);
      rows.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(row_gray);
    }
  const cv::Mat flat(120, 200, CV_8UC1, cv::Scalar(90));
  const cv::Point2f p(60.5f, 50.5f);
  const cv::Point2f along_x(1, 0), along_y(0, 1), diagonal(0.6f, 0.8f);
  EXPECT_TRUE(vo::self_similar_along(bars, p, along_x));
  EXPECT_FALSE(vo::self_similar_along(bars, p, along_y));
  EXPECT_TRUE(vo::self_similar_along(rows, p, along_x));
  EXPECT_FALSE(vo::self_similar_along(rows, p, along_y));
  for (const cv::Point2f& d : {along_x, along_y, diagonal, -along_x}) {
    EXPECT_FALSE(vo::self_similar_along(noise, p, d));
    EXPECT_TRUE(vo::self_similar_along(flat, p, d));
    EXPECT_FALSE(vo::self_similar_along(noise, p, 7.0f * d)) << "any length of direction";
  }
  // Nothing to look along; a patch that does not fit whole cannot count as distinctive.
  EXPECT_FALSE(vo::self_similar_along(noise, p, cv::Point2f(0, 0)));
  EXPECT_TRUE(vo::self_similar_along(noise, cv::Point2f(2.0f, 50.0f), along_y));
}

TEST(BundleAdjustment, RecoversPerturbedPosesAndPoints) {
  vo::StereoIntrinsics cam;
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  vo::BaProblem truth;
  for (int k = 0; k < 5; ++k) {
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
    T_world_cam.translation() = Eigen::Vector3d(0.1 * k, 0.0, 1.2 * k);
    T_world_cam.linear() = Eigen::AngleAxisd(0.03 * k, Eigen::Vector3d::UnitY()).toRotationMatrix();
    truth.T_cam_world.push_back(T_world_cam.inverse());
    truth.fixed.push_back(k < 2);
  }
  for (int i = 0; i < 150; ++i)
    truth.points.emplace_back(8 * uni(rng), 2 * uni(rng), 15 + 10 * uni(rng));
  for (int k = 0; k < 5; ++k) {
    for (int i = 0; i < 150; ++i) {
      const Eigen::Vector3d p = truth.T_cam_world[k] * truth.points[i];
      const double u = cam.fx * p.x() / p.z() + cam.cx, v = cam.fy * p.y() / p.z() + cam.cy;
      truth.observations.push_back({k, i, u, v, (i % 3 == 0) ? u - cam.bf() / p.z() : NAN});
    }
  }
  vo::BaProblem problem = truth;
  for (int k = 2; k < 5; ++k) {
    problem.T_cam_world[k].translation() +=
        0.05 * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    problem.T_cam_world[k].linear() =
        Eigen::AngleAxisd(0.005, Eigen::Vector3d::UnitX()).toRotationMatrix() *
        problem.T_cam_world[k].linear();
  }
  for (Eigen::Vector3d& p : problem.points)
    p += 0.05 * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  const vo::BaSummary s = vo::bundle_adjust(problem, cam, 50, 1.5);
  EXPECT_LT(s.final_cost, 1e-6 * std::max(1.0, s.initial_cost));
  for (int k = 0; k < 5; ++k) {
    EXPECT_LT((problem.T_cam_world[k].translation() - truth.T_cam_world[k].translation()).norm(),
              1e-4)
        << k;
  }
  EXPECT_TRUE(problem.T_cam_world[0].isApprox(truth.T_cam_world[0]));  // fixed: untouched
  for (const vo::BaObservation& o : problem.observations)
    EXPECT_LT(vo::reprojection_error(problem, o, cam), 1e-3);
  vo::BaProblem no_gauge = truth;
  no_gauge.fixed.assign(5, false);
  EXPECT_THROW(vo::bundle_adjust(no_gauge, cam, 5, 1.5), std::invalid_argument);
}

// ---- the VO on rendered images -------------------------------------------------------------

}  // namespace
}  // namespace loopscan
