#include "loopscan/vo/stereo_match.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <vector>

namespace loopscan::vo {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Best disparity searching `other` at x + direction * d, d in [d_lo, d_hi] (clipped to the
// image). `direction` is -1 from the left image into the right one, +1 back.
double search(const cv::Mat& ref, const cv::Mat& other, int x, int y, int direction, int d_lo,
              int d_hi, int h, double uniqueness) {
  const int w = ref.cols;
  if (x - h < 0 || x + h >= w || y - h < 0 || y + h >= ref.rows) return kNaN;
  // Keep the matched window inside `other`.
  if (direction < 0) {
    d_hi = std::min(d_hi, x - h);
  } else {
    d_hi = std::min(d_hi, w - 1 - h - x);
  }
  d_lo = std::max(d_lo, 0);
  if (d_hi - d_lo < 2) return kNaN;
  thread_local std::vector<int> costs;
  costs.assign(static_cast<std::size_t>(d_hi - d_lo + 1), 0);
  const int n = d_hi - d_lo + 1;
  // The other row's pixels in disparity order, so the inner loop runs over contiguous d and
  // vectorises: line[i + m] is the pixel window column m sees at disparity d_lo + i (m mirrored
  // when searching leftwards).
  thread_local std::vector<std::uint8_t> line;
  line.resize(static_cast<std::size_t>(n + 2 * h));
  for (int dy = -h; dy <= h; ++dy) {
    const std::uint8_t* r = ref.ptr<std::uint8_t>(y + dy) + x - h;
    const std::uint8_t* o = other.ptr<std::uint8_t>(y + dy) + x - h;
    for (int m = 0; m < n + 2 * h; ++m)
      line[m] = direction < 0 ? o[2 * h - d_lo - m] : o[d_lo + m];
    for (int k = 0; k <= 2 * h; ++k) {
      const int a = r[k];
      const std::uint8_t* b = line.data() + (direction < 0 ? 2 * h - k : k);
      int* c = costs.data();
      for (int i = 0; i < n; ++i) c[i] += std::abs(a - static_cast<int>(b[i]));
    }
  }
  int best = 0;
  for (int i = 1; i < n; ++i)
    if (costs[i] < costs[best]) best = i;
  int second = std::numeric_limits<int>::max();
  for (int i = 0; i < n; ++i)
    if (std::abs(i - best) > 1 && costs[i] < second) second = costs[i];
  if (best == 0 || best == n - 1) return kNaN;
  if (second == 0 || costs[best] >= uniqueness * second) return kNaN;
  // Equiangular (V-shaped) sub-pixel fit: SAD grows linearly away from the match, so a
  // parabola would pull estimates towards whole pixels.
  const double c0 = costs[best - 1], c1 = costs[best], c2 = costs[best + 1];
  const double slope = std::max(c0, c2) - c1;
  const double offset = slope > 0 ? 0.5 * (c0 - c2) / slope : 0.0;
  return d_lo + best + std::clamp(offset, -0.5, 0.5);
}

}  // namespace

double match_disparity(const cv::Mat& left, const cv::Mat& right, int x, int y,
                       const StereoSearch& s) {
  CV_Assert(left.type() == CV_8UC1 && right.type() == CV_8UC1 && left.size() == right.size());
  // No disparity is larger than the image is wide: the search range is clamped to it before
  // the conversion (a huge bf / depth ratio would overflow int).
  const double widest = left.cols;
  if (!(s.min_disparity <= s.max_disparity)) return kNaN;  // also NaN bounds
  const int d_lo = static_cast<int>(std::floor(std::clamp(s.min_disparity, 0.0, widest)));
  const int d_hi = static_cast<int>(std::ceil(std::clamp(s.max_disparity, 0.0, widest)));
  const double d = search(left, right, x, y, -1, d_lo, d_hi, s.half_window, s.uniqueness);
  if (!std::isfinite(d) || !s.left_right_check) return d;
  const int xr = static_cast<int>(std::lround(x - d));
  const double back = search(right, left, xr, y, +1, d_lo, d_hi, s.half_window, s.uniqueness);
  return std::isfinite(back) && std::abs(back - d) <= 1.0 ? d : kNaN;
}

}  // namespace loopscan::vo
