#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "loopscan/report/colormap.hpp"
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

// Range of the finite per-point values of all value-coloured series ([0, 1] without any).
void color_range(const std::vector<Series>& series, double& lo, double& hi) {
  lo = std::numeric_limits<double>::infinity();
  hi = -lo;
  for (const Series& s : series) {
    for (const double v : s.value) {
      if (!std::isfinite(v)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  if (!(lo <= hi)) lo = 0, hi = 1;
  if (hi == lo) hi = lo + 1;
}

std::string series_color(const Series& s, std::size_t index) {
  return s.color.empty() ? kPalette[index % kPalette.size()] : s.color;
}

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

// Calls emit(i, x0, y0, x1, y1, joined) for each drawable segment (points i-1, i) in pixels,
// clipped to the frame; `joined`: it starts where the previous emitted segment ended.
// Non-finite points break the line.
template <typename Emit>
void for_each_segment(const Series& s, const PlotFrame& f, Emit&& emit) {
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
    emit(i, x0, y0, x1, y1, !start_clipped);
    pen_at_prev = (x1 == end_x && y1 == end_y);
  }
}

// Path data of a polyline.
std::string line_path(const Series& s, const PlotFrame& f) {
  std::string d;
  for_each_segment(s, f, [&](std::size_t, double x0, double y0, double x1, double y1, bool joined) {
    if (!joined) d += (d.empty() ? "M" : " M") + svg_px(x0) + "," + svg_px(y0);
    d += " L" + svg_px(x1) + "," + svg_px(y1);
  });
  return d;
}

// A value-coloured polyline as one path per colour step (a few dozen elements, not one per
// segment); each segment takes the colour of its end points' mean value.
std::string value_paths(const Series& s, const PlotFrame& f, double lo, double hi) {
  constexpr int kSteps = 24;
  std::array<std::string, kSteps> d;
  int last_step = -1;  // the step whose path ends where a joined segment starts
  for_each_segment(s, f,
                   [&](std::size_t i, double x0, double y0, double x1, double y1, bool joined) {
                     const double v = i < s.value.size() ? 0.5 * (s.value[i - 1] + s.value[i]) : lo;
                     double t = hi > lo ? (v - lo) / (hi - lo) : 0.0;
                     t = std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.0;  // before the cast
                     const int k = std::min(static_cast<int>(t * kSteps), kSteps - 1);
                     if (!(joined && last_step == k))
                       d[k] += (d[k].empty() ? "M" : " M") + svg_px(x0) + "," + svg_px(y0);
                     d[k] += " L" + svg_px(x1) + "," + svg_px(y1);
                     last_step = k;
                   });
  std::string out;
  for (int k = 0; k < kSteps; ++k) {
    if (d[k].empty()) continue;
    out += "<path d=\"" + d[k] + "\" fill=\"none\" stroke=\"" + scale_color((k + 0.5) / kSteps) +
           "\" stroke-width=\"" + svg_px(s.width) + "\" stroke-linejoin=\"round\"/>\n";
  }
  return out;
}

// Path data of one circle per point inside the frame (two arcs each).
std::string marker_path(const Series& s, const PlotFrame& f) {
  std::string d;
  const std::size_t n = std::min(s.x.size(), s.y.size());
  const std::string r = svg_px(kMarkerRadius);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = f.to_px_x(s.x[i]);
    const double y = f.to_px_y(s.y[i]);
    if (!(x >= f.left && x <= f.right && y >= f.top && y <= f.bottom)) continue;  // also NaN
    if (!d.empty()) d += ' ';
    d += "M" + svg_px(x - kMarkerRadius) + "," + svg_px(y) + " a" + r + "," + r + " 0 1,0 " +
         svg_px(2 * kMarkerRadius) + ",0 a" + r + "," + r + " 0 1,0 " + svg_px(-2 * kMarkerRadius) +
         ",0";
  }
  return d;
}

std::string dash_attribute(const Series& s) {
  return s.dash.empty() ? "" : " stroke-dasharray=\"" + xml_escape(s.dash) + "\"";
}

std::string axes(const PlotFrame& f) {
  const Ticks xt = nice_ticks(f.tick_x_min, f.tick_x_max, tick_target(f.right - f.left));
  const Ticks yt = nice_ticks(f.tick_y_min, f.tick_y_max, tick_target(f.bottom - f.top));
  std::string grid = "<g class=\"grid\" stroke=\"#e0e0e0\" stroke-width=\"1\">\n";
  std::string marks = "<g class=\"ticks\" stroke=\"black\" stroke-width=\"1\">\n";
  std::string labels = "<g class=\"tick-labels\" fill=\"black\">\n";
  for (const double v : xt.values) {
    const double x = std::clamp(f.to_px_x(v), f.left, f.right);
    grid += svg_line(x, f.top, x, f.bottom);
    marks += svg_line(x, f.bottom, x, f.bottom + 5);
    labels += svg_text(x, f.bottom + 18, "middle", format_trimmed(v, xt.decimals));
  }
  for (const double v : yt.values) {
    const double y = std::clamp(f.to_px_y(v), f.top, f.bottom);
    grid += svg_line(f.left, y, f.right, y);
    marks += svg_line(f.left - 5, y, f.left, y);
    labels += svg_text(f.left - 8, y, "end", format_trimmed(v, yt.decimals), " dy=\"0.32em\"");
  }
  return grid + "</g>\n" + marks + "</g>\n" + labels + "</g>\n";
}

// Legend below the x-axis label: outside the data, whatever the data.
std::string legend(const std::vector<Series>& series, const PlotFrame& f, bool points) {
  if (f.legend_rows == 0) return "";
  std::size_t max_chars = 0;
  for (const Series& s : series) max_chars = std::max(max_chars, utf8_length(s.name));
  const double row_h = PlotFrame::kLegendRow;
  const double w = 40.0 + 7.0 * static_cast<double>(max_chars);
  const double h = 8.0 + row_h * f.legend_rows;
  const double x = f.left;
  double y = f.legend_top;
  std::string out = "<g class=\"legend\">\n<rect x=\"" + svg_px(x) + "\" y=\"" + svg_px(y) +
                    "\" width=\"" + svg_px(w) + "\" height=\"" + svg_px(h) +
                    "\" fill=\"white\" fill-opacity=\"0.85\" stroke=\"#999999\"/>\n";
  y += 4.0 + row_h / 2.0;
  for (std::size_t i = 0; i < series.size(); ++i) {
    const Series& s = series[i];
    if (s.name.empty()) continue;
    const std::string color =
        s.value.empty() || points ? xml_escape(series_color(s, i)) : scale_color(0.5);
    if (points) {
      out += "<circle cx=\"" + svg_px(x + 16) + "\" cy=\"" + svg_px(y) + "\" r=\"3\" fill=\"" +
             color + "\"/>\n";
    } else {
      out += "<line x1=\"" + svg_px(x + 6) + "\" y1=\"" + svg_px(y) + "\" x2=\"" + svg_px(x + 26) +
             "\" y2=\"" + svg_px(y) + "\" stroke=\"" + color + "\" stroke-width=\"2\"" +
             dash_attribute(s) + "/>\n";
    }
    out += svg_text(x + 32, y, "start", s.name, " dy=\"0.32em\"");
    y += row_h;
  }
  return out + "</g>\n";
}

}  // namespace

std::string line_plot_svg(const std::vector<Series>& series, const PlotOptions& options) {
  const PlotFrame f = make_frame(series, options);
  const std::string w = svg_px(f.width);
  const std::string h = svg_px(f.height);
  std::string svg = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  svg += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + w + "\" height=\"" + h +
         "\" viewBox=\"0 0 " + w + " " + h + "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  svg += "<rect x=\"0\" y=\"0\" width=\"" + w + "\" height=\"" + h + "\" fill=\"white\"/>\n";
  svg += axes(f);

  svg += "<g class=\"series\">\n";
  double lo = options.color_min, hi = options.color_max;
  if (!(hi > lo)) color_range(series, lo, hi);
  for (std::size_t i = 0; i < series.size(); ++i) {
    const Series& s = series[i];
    if (!s.value.empty() && !options.points) {
      svg += value_paths(s, f, lo, hi);
      continue;
    }
    const std::string color = xml_escape(series_color(s, i));
    const std::string style =
        options.points ? "fill=\"" + color + "\" stroke=\"none\""
                       : "fill=\"none\" stroke=\"" + color + "\" stroke-width=\"" +
                             svg_px(s.width) + "\" stroke-linejoin=\"round\"" + dash_attribute(s);
    const std::string d = options.points ? marker_path(s, f) : line_path(s, f);
    svg += "<path d=\"" + d + "\" " + style + "/>\n";
  }
  svg += "</g>\n";

  svg += "<rect class=\"frame\" x=\"" + svg_px(f.left) + "\" y=\"" + svg_px(f.top) + "\" width=\"" +
         svg_px(f.right - f.left) + "\" height=\"" + svg_px(f.bottom - f.top) +
         "\" fill=\"none\" stroke=\"black\"/>\n";
  const double mid_x = (f.left + f.right) / 2.0;
  const double mid_y = (f.top + f.bottom) / 2.0;
  svg += svg_text(mid_x, f.top - 12, "middle", options.title, " font-size=\"14\"");
  svg += svg_text(mid_x, f.bottom + 40, "middle", options.x_label);
  svg += svg_text(18, mid_y, "middle", options.y_label,
                  " transform=\"rotate(-90 18 " + svg_px(mid_y) + ")\"");
  if (options.overlay) svg += options.overlay(f);
  svg += legend(series, f, options.points);
  if (f.colorbar) {
    svg += colorbar_svg(f.right + 16, f.top, 14, f.bottom - f.top, lo, hi, options.color_label);
  }
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
