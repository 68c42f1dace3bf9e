#include "loopscan/vo/image_points.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

namespace loopscan::vo {

StereoSearch stereo_search_for(const StereoIntrinsics& camera, const VoConfig& config,
                               double min_depth_m, double max_depth_m, bool left_right_check) {
  StereoSearch s;
  s.min_disparity = camera.bf() / max_depth_m;
  s.max_disparity = camera.bf() / min_depth_m;
  s.half_window = config.stereo_half_window;
  s.uniqueness = config.stereo_uniqueness;
  s.left_right_check = left_right_check;
  return s;
}

std::vector<cv::Point2f> detect_grid_corners(const cv::Mat& image,
                                             const std::vector<cv::Point2f>& occupied,
                                             const VoConfig& config) {
  const int cols = config.grid_cols, rows = config.grid_rows;
  const double cell_w = static_cast<double>(image.cols) / cols;
  const double cell_h = static_cast<double>(image.rows) / rows;
  auto cell_of = [&](const cv::Point2f& p) {
    const int cx = std::clamp(static_cast<int>(p.x / cell_w), 0, cols - 1);
    const int cy = std::clamp(static_cast<int>(p.y / cell_h), 0, rows - 1);
    return cy * cols + cx;
  };
  std::vector<char> taken(static_cast<std::size_t>(cols * rows), 0);
  for (const cv::Point2f& p : occupied) taken[cell_of(p)] = 1;
  std::vector<cv::KeyPoint> corners;
  cv::FAST(image, corners, config.fast_threshold, true);
  std::vector<int> best(taken.size(), -1);
  const float border = static_cast<float>(config.stereo_half_window + 2);
  for (int i = 0; i < static_cast<int>(corners.size()); ++i) {
    const cv::Point2f& p = corners[i].pt;
    if (p.x < border || p.y < border || p.x >= image.cols - border || p.y >= image.rows - border)
      continue;
    const int c = cell_of(p);
    if (taken[c]) continue;
    if (best[c] < 0 || corners[i].response > corners[best[c]].response) best[c] = i;
  }
  std::vector<cv::Point2f> out;
  for (int b : best)
    if (b >= 0) out.push_back(corners[b].pt);
  return out;
}

bool self_similar_along(const cv::Mat& image, const cv::Point2f& p, const cv::Point2f& direction) {
  constexpr int kPatch = 11;
  constexpr double kSelfSimilarNcc = 0.8;
  constexpr double kFlatRms = 1.0;  // gray levels
  const float length = std::hypot(direction.x, direction.y);
  if (!(length > 0)) return false;  // no line to look along
  const cv::Point2f unit = direction / length;
  const cv::Size size(kPatch, kPatch);
  const float half = kPatch / 2 + 1;
  auto inside = [&](const cv::Point2f& q) {
    return q.x >= half && q.y >= half && q.x <= image.cols - 1 - half &&
           q.y <= image.rows - 1 - half;
  };
  auto zero_mean = [&](const cv::Point2f& centre, cv::Mat& patch) {
    cv::getRectSubPix(image, size, centre, patch, CV_32F);
    patch -= cv::mean(patch)[0];
    return cv::norm(patch);
  };
  // A patch that cannot be compared whole is not evidence of anything: counted as alike.
  if (!inside(p)) return true;
  cv::Mat reference, other;
  const double reference_norm = zero_mean(p, reference);
  if (reference_norm < kFlatRms * kPatch) return true;
  for (int step = 4; step <= 40; ++step) {
    const cv::Point2f q = p + static_cast<float>(step) * unit;
    if (!inside(q)) break;
    const double other_norm = zero_mean(q, other);
    if (other_norm > 0 && reference.dot(other) / (reference_norm * other_norm) > kSelfSimilarNcc)
      return true;
  }
  return false;
}

namespace {

// The gray of the surface beside an edge pixel: 2 px along the gradient, on the side where the
// gradient is weaker. The edge pixel's own gray is a mix of both sides that changes with the
// edge's sub-pixel position from one visit to the next; on the rendered city this lifts
// DELIGHT's AUC from 0.55 to 0.80 (docs/experiments/vo-city.md).
float surface_gray(const cv::Mat& image, const std::vector<float>& magnitude, int x, int y) {
  const int w = image.cols, h = image.rows;
  const float gx = 0.5f * (static_cast<float>(image.at<std::uint8_t>(y, x + 1)) -
                           image.at<std::uint8_t>(y, x - 1));
  const float gy = 0.5f * (static_cast<float>(image.at<std::uint8_t>(y + 1, x)) -
                           image.at<std::uint8_t>(y - 1, x));
  const float norm = std::sqrt(gx * gx + gy * gy);
  if (!(norm > 0)) return image.at<std::uint8_t>(y, x);
  const int dx = static_cast<int>(std::lround(2.0f * gx / norm));
  const int dy = static_cast<int>(std::lround(2.0f * gy / norm));
  const int ax = std::clamp(x + dx, 1, w - 2), ay = std::clamp(y + dy, 1, h - 2);
  const int bx = std::clamp(x - dx, 1, w - 2), by = std::clamp(y - dy, 1, h - 2);
  const bool a_flatter = magnitude[static_cast<std::size_t>(ay) * w + ax] <
                         magnitude[static_cast<std::size_t>(by) * w + bx];
  return a_flatter ? image.at<std::uint8_t>(ay, ax) : image.at<std::uint8_t>(by, bx);
}

}  // namespace

std::vector<CameraPoint> select_gradient_points(const cv::Mat& left, const cv::Mat& right,
                                                const StereoIntrinsics& camera,
                                                const VoConfig& config) {
  const int target = std::max(1, config.points_per_keyframe);
  const int block = std::max(
      2, static_cast<int>(std::lround(std::sqrt(left.cols * left.rows / (2.0 * target)))));
  const StereoSearch search =
      stereo_search_for(camera, config, config.min_depth_m, config.point_max_depth_m, true);
  const int margin = config.stereo_half_window + 1;
  struct Candidate {
    CameraPoint point;
    float gradient;
  };
  std::vector<Candidate> found;
  // Gradient magnitude (central differences) and, as DSO does, a threshold per region: the
  // region's median gradient plus a margin, so that weak uniform texture (asphalt) yields few
  // points and every textured part of the image some.
  const int w = left.cols, h = left.rows;
  std::vector<float> magnitude(static_cast<std::size_t>(w) * h, 0.0f);
  for (int y = 1; y + 1 < h; ++y) {
    const std::uint8_t* up = left.ptr<std::uint8_t>(y - 1);
    const std::uint8_t* row = left.ptr<std::uint8_t>(y);
    const std::uint8_t* down = left.ptr<std::uint8_t>(y + 1);
    float* m = magnitude.data() + static_cast<std::size_t>(y) * w;
    for (int x = 1; x + 1 < w; ++x) {
      const float gx = 0.5f * (static_cast<float>(row[x + 1]) - row[x - 1]);
      const float gy = 0.5f * (static_cast<float>(down[x]) - up[x]);
      m[x] = std::sqrt(gx * gx + gy * gy);
    }
  }
  const int region = std::max(8, static_cast<int>(std::lround(32 * pixel_scale(camera))));
  const int rx = (w + region - 1) / region, ry = (h + region - 1) / region;
  std::vector<float> threshold(static_cast<std::size_t>(rx) * ry);
  for (int j = 0; j < ry; ++j) {
    for (int i = 0; i < rx; ++i) {
      int histogram[256] = {};
      int n = 0;
      for (int y = j * region; y < std::min(h, (j + 1) * region); ++y)
        for (int x = i * region; x < std::min(w, (i + 1) * region); ++x, ++n)
          ++histogram[std::min(255, static_cast<int>(magnitude[static_cast<std::size_t>(y) * w + x]))];
      int median = 0;
      for (int count = 0; median < 255 && (count += histogram[median]) < (n + 1) / 2;) ++median;
      threshold[static_cast<std::size_t>(j) * rx + i] = static_cast<float>(
          std::max(config.point_min_gradient, median + config.point_gradient_over_median));
    }
  }
  for (int by = margin; by + block <= left.rows - margin; by += block) {
    for (int bx = margin; bx + block <= left.cols - margin; bx += block) {
      const int cx = std::min(rx - 1, (bx + block / 2) / region);
      const int cy = std::min(ry - 1, (by + block / 2) / region);
      float best_g = threshold[static_cast<std::size_t>(cy) * rx + cx];
      int best_x = -1, best_y = -1;
      for (int y = by; y < by + block; ++y) {
        const float* m = magnitude.data() + static_cast<std::size_t>(y) * w;
        for (int x = bx; x < bx + block; ++x) {
          if (m[x] > best_g) {
            best_g = m[x];
            best_x = x;
            best_y = y;
          }
        }
      }
      if (best_x < 0) continue;
      const double d = match_disparity(left, right, best_x, best_y, search);
      if (!std::isfinite(d) || d <= 0) continue;
      CameraPoint p;
      p.p_cam = back_project(camera, best_x, best_y, d);
      if (p.p_cam.z() < config.min_depth_m || p.p_cam.z() > config.point_max_depth_m) continue;
      p.gray = surface_gray(left, magnitude, best_x, best_y);
      p.u = static_cast<float>(best_x);
      p.v = static_cast<float>(best_y);
      found.push_back({p, best_g});
    }
  }
  if (static_cast<int>(found.size()) > target) {
    std::nth_element(found.begin(), found.begin() + target, found.end(),
                     [](const Candidate& a, const Candidate& b) { return a.gradient > b.gradient; });
    found.resize(static_cast<std::size_t>(target));
  }
  std::vector<CameraPoint> out;
  out.reserve(found.size());
  for (const Candidate& c : found) out.push_back(c.point);
  return out;
}

}  // namespace loopscan::vo
