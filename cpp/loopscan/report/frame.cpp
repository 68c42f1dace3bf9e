#include "loopscan/report/frame.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace loopscan::report {

namespace {

// Margins leave room for the title, tick labels and axis labels.
constexpr double kMarginLeft = 64.0;
constexpr double kMarginRight = 20.0;
constexpr double kMarginTop = 36.0;
constexpr double kMarginBottom = 52.0;
constexpr double kPadFraction = 0.05;
constexpr double kColorbarWidth = 90.0;

struct Range {
  double lo, hi;
};

bool usable(double lo, double hi) {
  return std::isfinite(lo) && std::isfinite(hi) && hi > lo && std::isfinite(hi - lo);
}

// Extent of the finite points (both coordinates finite) along one axis, padded.
Range data_range(const std::vector<Series>& series, bool x_axis) {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (const Series& s : series) {
    const std::size_t n = std::min(s.x.size(), s.y.size());
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      const double v = x_axis ? s.x[i] : s.y[i];
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  if (!(lo <= hi)) return {0.0, 1.0};  // no data
  if (hi == lo) {
    const double half = std::max(1.0, std::abs(lo) * kPadFraction);
    return {lo - half, hi + half};
  }
  const double pad = (hi - lo) * kPadFraction;
  return {lo - pad, hi + pad};
}

}  // namespace

Ticks nice_ticks(double lo, double hi, int target) {
  Ticks ticks;
  if (!usable(lo, hi)) return ticks;
  target = std::max(target, 1);
  const double raw = (hi - lo) / target;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  const double norm = raw / magnitude;
  const double mult = norm < 1.5 ? 1.0 : norm < 3.0 ? 2.0 : norm < 7.0 ? 5.0 : 10.0;
  const double step = mult * magnitude;
  // A small slack keeps end points such as 1.0 = 5 * 0.2 despite rounding.
  const double eps = 1e-9;
  const double first = std::ceil(lo / step - eps);
  const double last = std::floor(hi / step + eps);
  if (!(last - first < 1000.0)) return ticks;
  for (double k = first; k <= last; k += 1.0) ticks.values.push_back(k * step);
  ticks.decimals = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
  return ticks;
}

int tick_target(double pixels) { return std::clamp(static_cast<int>(pixels / 100.0 + 0.5), 2, 10); }

PlotFrame make_frame(const std::vector<Series>& series, const PlotOptions& options) {
  PlotFrame f;
  for (const Series& s : series) {
    f.legend_rows += s.name.empty() ? 0 : 1;
    f.colorbar = f.colorbar || (!s.value.empty() && !options.points);  // markers: palette
  }
  const double legend_h = f.legend_rows > 0 ? 10.0 + PlotFrame::kLegendRow * f.legend_rows : 0.0;
  const double colorbar_w = f.colorbar ? kColorbarWidth : 0.0;
  // A canvas too small for the margins would invert the plot area.
  f.width = std::max(options.width, 160) + colorbar_w;
  f.height = std::max(options.height, 120) + legend_h;
  f.left = kMarginLeft;
  f.top = kMarginTop;
  f.right = f.width - kMarginRight - colorbar_w;
  f.bottom = f.height - kMarginBottom - legend_h;
  f.legend_top = f.bottom + kMarginBottom - 2.0;

  Range x{options.x_min, options.x_max};
  Range y{options.y_min, options.y_max};
  const bool fixed_x = usable(x.lo, x.hi), fixed_y = usable(y.lo, y.hi);
  if (!fixed_x) x = data_range(series, true);
  if (!fixed_y) y = data_range(series, false);
  const Range tick_x = x, tick_y = y;
  const double pad = std::max(0.0, options.pad);
  if (fixed_x) x = {x.lo - pad * (x.hi - x.lo), x.hi + pad * (x.hi - x.lo)};
  if (fixed_y) y = {y.lo - pad * (y.hi - y.lo), y.hi + pad * (y.hi - y.lo)};

  if (options.equal_aspect) {
    // Widen the axis with the larger scale so both use the smaller pixels-per-unit.
    const double pw = f.right - f.left;
    const double ph = f.bottom - f.top;
    const double scale = std::min(pw / (x.hi - x.lo), ph / (y.hi - y.lo));
    const double cx = (x.lo + x.hi) / 2.0;
    const double cy = (y.lo + y.hi) / 2.0;
    x = {cx - pw / scale / 2.0, cx + pw / scale / 2.0};
    y = {cy - ph / scale / 2.0, cy + ph / scale / 2.0};
  }
  f.x_min = x.lo;
  f.x_max = x.hi;
  f.y_min = y.lo;
  f.y_max = y.hi;
  // Padding leaves the ticks on the requested range; equal aspect ticks the widened one.
  const bool keep_ticks = pad > 0 && !options.equal_aspect;
  f.tick_x_min = keep_ticks && fixed_x ? tick_x.lo : x.lo;
  f.tick_x_max = keep_ticks && fixed_x ? tick_x.hi : x.hi;
  f.tick_y_min = keep_ticks && fixed_y ? tick_y.lo : y.lo;
  f.tick_y_max = keep_ticks && fixed_y ? tick_y.hi : y.hi;
  return f;
}

}  // namespace loopscan::report
