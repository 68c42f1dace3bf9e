#pragma once
// General-purpose SVG line / scatter plots (PR curves, trajectories, timing figures).
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace loopscan::report {

struct PlotFrame;

struct Series {
  // A constructor (not aggregate initialisation) so {name, x, y, color} leaves the styling
  // fields at their defaults without missing-initializer warnings.
  Series(std::string name_ = "", std::vector<double> x_ = {}, std::vector<double> y_ = {},
         std::string color_ = "")
      : name(std::move(name_)), x(std::move(x_)), y(std::move(y_)), color(std::move(color_)) {}
  std::string name;  // legend text; series with empty names are left out of the legend
  std::vector<double> x, y;
  std::string color;  // any SVG colour; empty = automatic palette
  // Per point: when set, each segment takes the colour scale's colour of its mean value instead
  // of `color`, and the plot gets a colour bar (PlotOptions::color_label).
  std::vector<double> value;
  std::string dash;    // SVG stroke-dasharray, e.g. "6,4"; empty = solid
  double width = 1.5;  // stroke width in pixels
};

struct PlotOptions {
  std::string title, x_label = "Recall", y_label = "Precision";
  // An axis whose max is not greater than its min (e.g. both 0) is ranged from the data.
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
  int width = 640, height = 480;
  bool points = false;        // markers instead of lines
  bool equal_aspect = false;  // one data unit = same pixels on both axes (ranges are widened)
  // Fixed ranges are widened by this fraction on each side, so lines on a limit (precision 1,
  // recall 0) are drawn inside the frame instead of on it. Ticks stay on the unwidened range.
  double pad = 0;
  std::string color_label;              // colour bar label of value-coloured series
  double color_min = 0, color_max = 0;  // colour range; auto (data range) when max <= min
  // Extra SVG drawn over the data (markers, annotations), placed with the plot's own frame.
  std::function<std::string(const PlotFrame&)> overlay;
};

// A complete SVG document: frame, grid, ticks with labels, axis labels, title, legend below the
// plot area (never over the data), colour bar when a series is value-coloured. All text
// is XML-escaped, lines are clipped to the frame, non-finite points break the line. Each series
// is one <path> element (a value-coloured one: one per colour step used). Deterministic: same
// input, same bytes.
std::string line_plot_svg(const std::vector<Series>& series, const PlotOptions& options);

// Equal-aspect plot with ranges taken from the data, for maps and trajectories.
std::string map_plot_svg(const std::vector<Series>& series, const std::string& title,
                         const std::string& x_label = "x [m]",
                         const std::string& y_label = "z [m]");

}  // namespace loopscan::report
