#pragma once
// General-purpose SVG line / scatter plots (PR curves, trajectories, timing figures).
#include <string>
#include <vector>

namespace loopscan::report {

struct Series {
  std::string name;  // legend text; series with empty names are left out of the legend
  std::vector<double> x, y;
  std::string color;  // any SVG colour; empty = automatic palette
};

struct PlotOptions {
  std::string title, x_label = "Recall", y_label = "Precision";
  // An axis whose max is not greater than its min (e.g. both 0) is ranged from the data.
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
  int width = 640, height = 480;
  bool points = false;        // markers instead of lines
  bool equal_aspect = false;  // one data unit = same pixels on both axes (ranges are widened)
};

// A complete SVG document: frame, grid, ticks with labels, axis labels, title, legend. All text
// is XML-escaped, lines are clipped to the frame, non-finite points break the line. Each series
// is exactly one <path> element. Deterministic: same input, same bytes.
std::string line_plot_svg(const std::vector<Series>& series, const PlotOptions& options);

// Equal-aspect plot with ranges taken from the data, for maps and trajectories.
std::string map_plot_svg(const std::vector<Series>& series, const std::string& title,
                         const std::string& x_label = "x [m]",
                         const std::string& y_label = "z [m]");

}  // namespace loopscan::report
