#pragma once
// Angle binning without calling std::atan2 for every point: a branch-free, range-reduced series
// accurate to ~2e-11 rad, with an exact std::atan2 fallback for the rare values that land next
// to a bin boundary. Every bin is therefore floor() of the exact angle, only cheaper.
#include <cmath>

namespace loopscan {

// Approximate atan2(y, x) in [-pi, pi], error ~2e-11 rad. Written with selects only, so that
// loops over many points vectorise and do not mispredict.
inline double approx_atan2(double y, double x) {
  constexpr double kSqrt3 = 1.7320508075688772;
  constexpr double kTan15 = 0.2679491924311227;  // 2 - sqrt(3)
  const double ax = std::fabs(x), ay = std::fabs(y);
  const bool steep = ay > ax;
  const double mx = steep ? ay : ax, mn = steep ? ax : ay;
  const double t = mx > 0.0 ? mn / mx : 0.0;
  // atan(t) = pi/6 + atan((sqrt3 t - 1) / (sqrt3 + t)) brings |u| below tan(15 deg).
  const bool reduce = t > kTan15;
  const double u = reduce ? (kSqrt3 * t - 1.0) / (kSqrt3 + t) : t;
  const double u2 = u * u;
  double s = -1.0 / 15.0;
  s = s * u2 + 1.0 / 13.0;
  s = s * u2 - 1.0 / 11.0;
  s = s * u2 + 1.0 / 9.0;
  s = s * u2 - 1.0 / 7.0;
  s = s * u2 + 1.0 / 5.0;
  s = s * u2 - 1.0 / 3.0;
  double a = (reduce ? M_PI / 6.0 : 0.0) + (u + u * u2 * s);  // Taylor to u^15: err < u^17/17
  a = steep ? M_PI / 2.0 - a : a;
  a = x < 0.0 ? M_PI - a : a;
  return std::copysign(a, y);  // -0.0 gives -pi / -0, like atan2
}

// floor((atan2(y, x) + offset) * inv_width), identical to the exact formula, for offsets that
// keep the value non-negative (pi for azimuths, pi/2 for elevations).
inline int angle_bin(double y, double x, double offset, double inv_width) {
  const double v = (approx_atan2(y, x) + offset) * inv_width;
  const int bin = static_cast<int>(v);  // v >= 0: truncation is floor
  const double frac = v - bin;
  constexpr double kMargin = 1e-7;  // in bins: ~1.7e-9 rad at 1 degree, far above the error
  if (frac < kMargin || frac > 1.0 - kMargin) {
    return static_cast<int>(std::floor((std::atan2(y, x) + offset) * inv_width));
  }
  return bin;
}

}  // namespace loopscan

#include <vector>

namespace loopscan {

// floor((atan2(y, x) + offset) * inv_width) for bin widths that divide 90 degrees and offsets
// that are whole bins (1-degree polar cells, 6-degree Scan Context sectors, 22.5-degree M2DP
// sectors): quadrant/octant symmetry, one division and a lookup table over tan(angle) instead
// of an arctangent. Values within 1e-12 of a bin boundary (and exact zeros) take the exact
// std::atan2 path, so the result always equals the formula.
class AngleBinner {
 public:
  AngleBinner(double inv_width, double offset) : inv_(inv_width), offset_(offset) {
    const double per_quadrant = (M_PI / 2.0) * inv_width;
    quadrant_bins_ = static_cast<int>(std::lround(per_quadrant));
    const double offset_bins = offset * inv_width;
    offset_bins_ = static_cast<int>(std::lround(offset_bins));
    usable_ = std::abs(per_quadrant - quadrant_bins_) < 1e-9 &&
              std::abs(offset_bins - offset_bins_) < 1e-9 && quadrant_bins_ >= 1 &&
              quadrant_bins_ <= 2048;
    if (!usable_) return;
    // Boundaries below 45 degrees: tan(k w), then a sentinel above every t in [0, 1].
    const int last = quadrant_bins_ / 2;
    tan_.resize(last + 2);
    for (int k = 0; k <= last; ++k) tan_[k] = std::tan(k * (M_PI / 2.0) / quadrant_bins_);
    tan_[last + 1] = 2.0;
    lut_.resize(kLut + 1);
    int k = 0;
    for (int i = 0; i <= kLut; ++i) {
      while (k + 1 <= last && tan_[k + 1] <= static_cast<double>(i) / kLut) ++k;
      lut_[i] = k;
    }
  }

  // For vectorised callers (scan_context_bins): the same tables and symmetries.
  bool usable() const { return usable_; }
  int quadrant_bins() const { return quadrant_bins_; }
  int offset_bins() const { return offset_bins_; }
  const std::vector<double>& boundaries() const { return tan_; }  // tan, then a sentinel 2

  int operator()(double y, double x) const {
    if (!usable_) return angle_bin(y, x, offset_, inv_);
    const double ax = std::fabs(x), ay = std::fabs(y);
    const bool steep = ay > ax;
    const double mx = steep ? ay : ax, mn = steep ? ax : ay;
    if (!(mn > 0.0)) return exact(y, x);  // on an axis (a boundary) or NaN
    const double t = mn / mx;             // tan of the angle to the nearer axis, in [0, 1]
    int k = lut_[static_cast<int>(t * kLut)];
    k += t >= tan_[k + 1];
    if (t - tan_[k] < 1e-12 || tan_[k + 1] - t < 1e-12) return exact(y, x);
    // Off every boundary: integer arithmetic over the symmetries, with selects, not branches
    // (the signs of x and y are unpredictable).
    const int Q = quadrant_bins_;
    const int kb = steep ? Q - k - 1 : k;             // bin of the first-quadrant angle
    const int upper = x >= 0 ? kb : 2 * Q - 1 - kb;   // bin of |angle| in [0, pi]
    return (y >= 0 ? upper : ~upper) + offset_bins_;  // floor(-v) = -floor(v) - 1 = ~floor(v)
  }

 private:
  int exact(double y, double x) const {
    return static_cast<int>(std::floor((std::atan2(y, x) + offset_) * inv_));
  }
  static constexpr int kLut = 4096;
  double inv_, offset_;
  int quadrant_bins_ = 0, offset_bins_ = 0;
  bool usable_ = false;
  std::vector<double> tan_;
  std::vector<int> lut_;
};

}  // namespace loopscan
