#include "loopscan/report/heatmap.hpp"

#include <algorithm>
#include <cmath>

#include "loopscan/report/colormap.hpp"
#include "loopscan/report/frame.hpp"
#include "loopscan/report/svg_text.hpp"

namespace loopscan::report {

std::string heatmap_svg(const Eigen::MatrixXd& values, const HeatmapOptions& o) {
  const int rows = static_cast<int>(values.rows()), cols = static_cast<int>(values.cols());
  const double left = 64, top = 40, w = cols * o.cell_px, h = rows * o.cell_px;
  const double width = left + w + 110, height = top + h + 56;
  double lo = o.lo, hi = o.hi;
  if (!(hi > lo)) {
    lo = values.size() > 0 ? std::min(0.0, values.minCoeff()) : 0.0;
    hi = values.size() > 0 ? values.maxCoeff() : 1.0;
    if (!(hi > lo)) hi = lo + 1.0;  // a constant image still gets a usable bar
  }
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + svg_px(width) +
                    "\" height=\"" + svg_px(height) + "\" viewBox=\"0 0 " + svg_px(width) + " " +
                    svg_px(height) + "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg += svg_text(left + w / 2, 22, "middle", o.title, " font-size=\"14\"");
  svg += "<g class=\"cells\" shape-rendering=\"crispEdges\">\n";
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      svg += "<rect x=\"" + svg_px(left + c * o.cell_px) + "\" y=\"" + svg_px(top + r * o.cell_px) +
             "\" width=\"" + std::to_string(o.cell_px) + "\" height=\"" +
             std::to_string(o.cell_px) + "\" fill=\"" +
             scale_color((values(r, c) - lo) / (hi - lo)) + "\"/>\n";
    }
  }
  svg += "</g>\n<rect class=\"frame\" x=\"" + svg_px(left) + "\" y=\"" + svg_px(top) +
         "\" width=\"" + svg_px(w) + "\" height=\"" + svg_px(h) +
         "\" fill=\"none\" stroke=\"black\"/>\n";
  // Ticks in axis units: value v sits at the fraction (v - first) / (last - first).
  const auto ticks_along = [](double first, double last, double pixels) {
    return nice_ticks(std::min(first, last), std::max(first, last), tick_target(pixels));
  };
  const Ticks xt = ticks_along(o.x_first, o.x_last, w);
  for (const double v : xt.values) {
    const double x = left + (v - o.x_first) / (o.x_last - o.x_first) * w;
    svg += svg_line(x, top + h, x, top + h + 5, " stroke=\"black\"");
    svg += svg_text(x, top + h + 18, "middle", format_trimmed(v, xt.decimals));
  }
  const Ticks yt = ticks_along(o.y_first, o.y_last, h);
  for (const double v : yt.values) {
    const double y = top + (v - o.y_first) / (o.y_last - o.y_first) * h;
    svg += svg_line(left - 5, y, left, y, " stroke=\"black\"");
    svg += svg_text(left - 8, y, "end", format_trimmed(v, yt.decimals), " dy=\"0.32em\"");
  }
  svg += svg_text(left + w / 2, top + h + 40, "middle", o.x_label);
  svg += svg_text(18, top + h / 2, "middle", o.y_label,
                  " transform=\"rotate(-90 18 " + svg_px(top + h / 2) + ")\"");
  svg += colorbar_svg(left + w + 16, top, 14, h, lo, hi, o.colorbar_label);
  return svg + "</svg>\n";
}

}  // namespace loopscan::report
