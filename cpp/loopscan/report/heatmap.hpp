#pragma once
// A matrix as an SVG image (e.g. a Scan Context: rings x sectors) on the viridis-like scale,
// with axes in the quantities the cells stand for, ticks and a colour bar.
#include <string>

#include <Eigen/Core>

namespace loopscan::report {

struct HeatmapOptions {
  std::string title, x_label, y_label, colorbar_label;
  // Axis values at the outer edges of the first and last column / row (row 0 is drawn on top).
  double x_first = 0, x_last = 1, y_first = 0, y_last = 1;
  int cell_px = 10;
  // Colour range; when hi <= lo it is [min(0, data min), data max].
  double lo = 0, hi = 0;
};

std::string heatmap_svg(const Eigen::MatrixXd& values, const HeatmapOptions& options);

}  // namespace loopscan::report
