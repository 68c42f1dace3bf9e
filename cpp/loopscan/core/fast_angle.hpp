#pragma once
// Angle binning without calling std::atan2 for every point: a range-reduced series that is
// accurate to ~2e-11 rad, with an exact std::atan2 fallback for the rare values that land
// next to a bin boundary. The bin of every point is therefore the same as floor() of the
// exact angle, only cheaper.
#include <cmath>

namespace loopscan {

// atan(t) for t in [0, 1].
inline double atan_unit(double t) {
  constexpr double kSqrt3 = 1.7320508075688772;
  constexpr double kTan15 = 0.2679491924311227;  // 2 - sqrt(3)
  const bool reduce = t > kTan15;
  // atan(t) = pi/6 + atan((sqrt3 t - 1) / (sqrt3 + t)) brings |u| below tan(15 deg).
  const double u = reduce ? (kSqrt3 * t - 1.0) / (kSqrt3 + t) : t;
  const double u2 = u * u;
  double s = -1.0 / 15.0;
  s = s * u2 + 1.0 / 13.0;
  s = s * u2 - 1.0 / 11.0;
  s = s * u2 + 1.0 / 9.0;
  s = s * u2 - 1.0 / 7.0;
  s = s * u2 + 1.0 / 5.0;
  s = s * u2 - 1.0 / 3.0;
  const double atan_u = u + u * u2 * s;  // Taylor series up to u^15, error < u^17 / 17
  return (reduce ? M_PI / 6.0 : 0.0) + atan_u;
}

// Approximate atan2(y, x) in [-pi, pi], error ~2e-11 rad.
inline double approx_atan2(double y, double x) {
  const double ax = std::fabs(x), ay = std::fabs(y);
  const double mx = ax > ay ? ax : ay, mn = ax > ay ? ay : ax;
  double a = mx > 0.0 ? atan_unit(mn / mx) : 0.0;
  if (ay > ax) a = M_PI / 2.0 - a;
  if (x < 0.0) a = M_PI - a;
  return y < 0.0 ? -a : a;
}

// floor((atan2(y, x) + offset) * inv_width), identical to the exact formula, for offsets that
// keep the value non-negative (pi for azimuths, pi/2 for elevations).
inline int angle_bin(double y, double x, double offset, double inv_width) {
  const double v = (approx_atan2(y, x) + offset) * inv_width;
  const double f = static_cast<double>(static_cast<int>(v));  // v >= 0: truncation is floor
  const double margin = 1e-7;  // in bins: ~1.7e-9 rad at 1 degree, far above the series error
  if (v - f < margin || f + 1.0 - v < margin) {
    return static_cast<int>(std::floor((std::atan2(y, x) + offset) * inv_width));
  }
  return static_cast<int>(f);
}

}  // namespace loopscan
