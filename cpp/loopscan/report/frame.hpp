#pragma once
// Plot layout: data ranges, "nice" ticks and the data -> SVG pixel mapping. Exposed so callers
// can place annotations on top of a plot and tests can check the mapping.
#include <vector>

#include "loopscan/report/plot.hpp"

namespace loopscan::report {

struct Ticks {
  std::vector<double> values;  // inside [lo, hi], multiples of the step
  int decimals = 0;            // digits needed to print the step exactly
};

// About `target` intervals with a step of 1, 2 or 5 times a power of ten; [0, 1] gives
// 0, 0.2, ..., 1. Empty for a non-finite or empty range.
Ticks nice_ticks(double lo, double hi, int target = 5);

// Tick intervals for an axis this many pixels long: about one per 100 px, so labels never
// collide (2 to 10).
int tick_target(double pixels);

struct PlotFrame {
  double width = 0, height = 0;                       // SVG canvas
  double left = 0, top = 0, right = 0, bottom = 0;    // plot area in pixels (top < bottom)
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;  // final data ranges
  double tick_x_min = 0, tick_x_max = 1, tick_y_min = 0, tick_y_max = 1;  // ranges given ticks
  int legend_rows = 0;    // named series, listed below the plot
  double legend_top = 0;  // y of the legend box (under the x-axis label)
  bool colorbar = false;  // a value-coloured line series: a colour bar right of the plot
  static constexpr double kLegendRow = 18.0;  // pixels per legend entry
  double to_px_x(double x) const { return left + (x - x_min) / (x_max - x_min) * (right - left); }
  double to_px_y(double y) const { return bottom - (y - y_min) / (y_max - y_min) * (bottom - top); }
};

// Applies auto ranges (data extent + 5 % padding), PlotOptions::pad and equal aspect to the
// options' ranges. The canvas grows by the legend's rows and a colour bar's width, so the plot
// area keeps the size the options ask for.
PlotFrame make_frame(const std::vector<Series>& series, const PlotOptions& options);

}  // namespace loopscan::report
