#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "loopscan/report/frame.hpp"
#include "loopscan/report/plot.hpp"
#include "loopscan/report/svg_text.hpp"

namespace loopscan::report {

namespace {

// Matplotlib's "tab10": distinguishable and familiar from the paper's figures.
constexpr std::array<const char*, 10> kPalette = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728",
                                                  "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
                                                  "#bcbd22", "#17becf"};
constexpr double kMarkerRadius = 2.5;

std::string px(double v) { return format_trimmed(v, 2); }

std::string series_color(const Series& s, std::size_t index) {
  return s.color.empty() ? kPalette[index % kPalette.size()] : s.color;
}

// Roughly one tick interval per 100 px keeps labels from colliding.
int tick_target(double pixels) { return std::clamp(static_cast<int>(pixels / 100.0 + 0.5), 2, 10); }

// Liang-Barsky: clips segment (x0,y0)-(x1,y1) to the plot area; false if nothing remains.
bool clip_segment(const PlotFrame& f, double& x0, double& y0, double& x1, double& y1) {
  const double dx = x1 - x0;
  const double dy = y1 - y0;
  double t0 = 0.0;
  double t1 = 1.0;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {x0 - f.left, f.right - x0, y0 - f.top, f.bottom - y0};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
      continue;
    }
    const double t = q[i] / p[i];
    if (p[i] < 0.0) {
      t0 = std::max(t0, t);
    } else {
      t1 = std::min(t1, t);
    }
    if (t0 > t1) return false;
  }
  const double sx = x0;
  const double sy = y0;
  x0 = sx + t0 * dx;
  y0 = sy + t0 * dy;
  x1 = sx + t1 * dx;
  y1 = sy + t1 * dy;
  return true;
}

// Path data of a polyline; non-finite points split it, parts outside the frame are clipped.
std::string line_path(const Series& s, const PlotFrame& f) {
  std::string d;
  const std::size_t n = std::min(s.x.size(), s.y.size());
  bool pen_at_prev = false;  // the pen sits at the (unclipped) previous point
  for (std::size_t i = 1; i < n; ++i) {
    if (!std::isfinite(s.x[i - 1]) || !std::isfinite(s.y[i - 1]) || !std::isfinite(s.x[i]) ||
        !std::isfinite(s.y[i])) {
      pen_at_prev = false;
      continue;
    }
    double x0 = f.to_px_x(s.x[i - 1]), y0 = f.to_px_y(s.y[i - 1]);
    double x1 = f.to_px_x(s.x[i]), y1 = f.to_px_y(s.y[i]);
    const double end_x = x1, end_y = y1;
    if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1) ||
        !clip_segment(f, x0, y0, x1, y1)) {
      pen_at_prev = false;
      continue;
    }
    const bool start_clipped =
        !pen_at_prev || x0 != f.to_px_x(s.x[i - 1]) || y0 != f.to_px_y(s.y[i - 1]);
    if (start_clipped) d += (d.empty() ? "M" : " M") + px(x0) + "," + px(y0);
    d += " L" + px(x1) + "," + px(y1);
    pen_at_prev = (x1 == end_x && y1 == end_y);
  }
  return d;
}

// Path data of one circle per point inside the frame (two arcs each).
std::string marker_path(const Series& s, const PlotFrame& f) {
  std::string d;
  const std::size_t n = std::min(s.x.size(), s.y.size());
  const std::string r = px(kMarkerRadius);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = f.to_px_x(s.x[i]);
    const double y = f.to_px_y(s.y[i]);
    if (!(x >= f.left && x <= f.right && y >= f.top && y <= f.bottom)) continue;  // also NaN
    if (!d.empty()) d += ' ';
    d += "M" + px(x - kMarkerRadius) + "," + px(y) + " a" + r + "," + r + " 0 1,0 " +
         px(2 * kMarkerRadius) + ",0 a" + r + "," + r + " 0 1,0 " + px(-2 * kMarkerRadius) + ",0";
  }
  return d;
}

std::string text_element(double x, double y, const std::string& anchor, const std::string& text,
                         const std::string& extra = "") {
  return "<text x=\"" + px(x) + "\" y=\"" + px(y) + "\" text-anchor=\"" + anchor + "\"" + extra +
         ">" + xml_escape(text) + "</text>\n";
}

std::string line_element(double x0, double y0, double x1, double y1) {
  return "<line x1=\"" + px(x0) + "\" y1=\"" + px(y0) + "\" x2=\"" + px(x1) + "\" y2=\"" + px(y1) +
         "\"/>\n";
}

std::string axes(const PlotFrame& f) {
  const Ticks xt = nice_ticks(f.x_min, f.x_max, tick_target(f.right - f.left));
  const Ticks yt = nice_ticks(f.y_min, f.y_max, tick_target(f.bottom - f.top));
  std::string grid = "<g class=\"grid\" stroke=\"#e0e0e0\" stroke-width=\"1\">\n";
  std::string marks = "<g class=\"ticks\" stroke=\"black\" stroke-width=\"1\">\n";
  std::string labels = "<g class=\"tick-labels\" fill=\"black\">\n";
  for (const double v : xt.values) {
    const double x = std::clamp(f.to_px_x(v), f.left, f.right);
    grid += line_element(x, f.top, x, f.bottom);
    marks += line_element(x, f.bottom, x, f.bottom + 5);
    labels += text_element(x, f.bottom + 18, "middle", format_trimmed(v, xt.decimals));
  }
  for (const double v : yt.values) {
    const double y = std::clamp(f.to_px_y(v), f.top, f.bottom);
    grid += line_element(f.left, y, f.right, y);
    marks += line_element(f.left - 5, y, f.left, y);
    labels += text_element(f.left - 8, y, "end", format_trimmed(v, yt.decimals), " dy=\"0.32em\"");
  }
  return grid + "</g>\n" + marks + "</g>\n" + labels + "</g>\n";
}

// Legend in the lower-left corner, where PR curves rarely go.
std::string legend(const std::vector<Series>& series, const PlotFrame& f, bool points) {
  std::size_t rows = 0;
  std::size_t max_chars = 0;
  for (const Series& s : series) {
    if (s.name.empty()) continue;
    ++rows;
    max_chars = std::max(max_chars, utf8_length(s.name));
  }
  if (rows == 0) return "";
  const double row_h = 18.0;
  const double w = 40.0 + 7.0 * static_cast<double>(max_chars);
  const double h = 8.0 + row_h * static_cast<double>(rows);
  const double x = f.left + 8.0;
  double y = f.bottom - 8.0 - h;
  std::string out = "<g class=\"legend\">\n<rect x=\"" + px(x) + "\" y=\"" + px(y) + "\" width=\"" +
                    px(w) + "\" height=\"" + px(h) +
                    "\" fill=\"white\" fill-opacity=\"0.85\" stroke=\"#999999\"/>\n";
  y += 4.0 + row_h / 2.0;
  for (std::size_t i = 0; i < series.size(); ++i) {
    const Series& s = series[i];
    if (s.name.empty()) continue;
    const std::string color = xml_escape(series_color(s, i));
    if (points) {
      out += "<circle cx=\"" + px(x + 16) + "\" cy=\"" + px(y) + "\" r=\"3\" fill=\"" + color +
             "\"/>\n";
    } else {
      out += "<line x1=\"" + px(x + 6) + "\" y1=\"" + px(y) + "\" x2=\"" + px(x + 26) + "\" y2=\"" +
             px(y) + "\" stroke=\"" + color + "\" stroke-width=\"2\"/>\n";
    }
    out += text_element(x + 32, y, "start", s.name, " dy=\"0.32em\"");
    y += row_h;
  }
  return out + "</g>\n";
}

}  // namespace

std::string line_plot_svg(const std::vector<Series>& series, const PlotOptions& options) {
  const PlotFrame f = make_frame(series, options);
  const std::string w = px(f.width);
  const std::string h = px(f.height);
  std::string svg = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  svg += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + w + "\" height=\"" + h +
         "\" viewBox=\"0 0 " + w + " " + h + "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  svg += "<rect x=\"0\" y=\"0\" width=\"" + w + "\" height=\"" + h + "\" fill=\"white\"/>\n";
  svg += axes(f);

  svg += "<g class=\"series\">\n";
  for (std::size_t i = 0; i < series.size(); ++i) {
    const std::string color = xml_escape(series_color(series[i], i));
    const std::string style = options.points
                                  ? "fill=\"" + color + "\" stroke=\"none\""
                                  : "fill=\"none\" stroke=\"" + color +
                                        "\" stroke-width=\"1.5\" stroke-linejoin=\"round\"";
    const std::string d = options.points ? marker_path(series[i], f) : line_path(series[i], f);
    svg += "<path d=\"" + d + "\" " + style + "/>\n";
  }
  svg += "</g>\n";

  svg += "<rect class=\"frame\" x=\"" + px(f.left) + "\" y=\"" + px(f.top) + "\" width=\"" +
         px(f.right - f.left) + "\" height=\"" + px(f.bottom - f.top) +
         "\" fill=\"none\" stroke=\"black\"/>\n";
  const double mid_x = (f.left + f.right) / 2.0;
  const double mid_y = (f.top + f.bottom) / 2.0;
  svg += text_element(mid_x, f.top - 12, "middle", options.title, " font-size=\"14\"");
  svg += text_element(mid_x, f.bottom + 40, "middle", options.x_label);
  svg += text_element(18, mid_y, "middle", options.y_label,
                      " transform=\"rotate(-90 18 " + px(mid_y) + ")\"");
  svg += legend(series, f, options.points);
  svg += "</svg>\n";
  return svg;
}

std::string map_plot_svg(const std::vector<Series>& series, const std::string& title,
                         const std::string& x_label, const std::string& y_label) {
  PlotOptions options;
  options.title = title;
  options.x_label = x_label;
  options.y_label = y_label;
  options.x_min = options.x_max = 0.0;  // auto range
  options.y_min = options.y_max = 0.0;
  options.equal_aspect = true;
  return line_plot_svg(series, options);
}

}  // namespace loopscan::report
