#include "loopscan/report/pr_plot.hpp"

#include <algorithm>

#include "loopscan/report/svg_text.hpp"

namespace loopscan::report {

namespace {

const char* const kDash = " \xE2\x80\x94 ";  // em dash, UTF-8

std::vector<eval::PrPoint> to_curve(const Series& s) {
  std::vector<eval::PrPoint> curve;
  const std::size_t n = std::min(s.x.size(), s.y.size());
  curve.reserve(n);
  for (std::size_t i = 0; i < n; ++i) curve.push_back({s.y[i], s.x[i]});
  return curve;
}

}  // namespace

Series pr_series(const std::vector<eval::PrPoint>& curve, const std::string& name,
                 const std::string& color) {
  Series s;
  s.name = name;
  s.color = color;
  s.x.reserve(curve.size());
  s.y.reserve(curve.size());
  for (const eval::PrPoint& p : curve) {
    s.x.push_back(p.recall);
    s.y.push_back(p.precision);
  }
  return s;
}

std::string pr_metrics_text(const Series& curve) {
  const std::vector<eval::PrPoint> points = to_curve(curve);
  return "AUC=" + format_fixed(eval::trapezoid_auc(points), 4) +
         ", recall@100%P=" + format_fixed(eval::recall_at_full_precision(points), 4);
}

std::string pr_curve_svg(const std::vector<Series>& curves, const std::string& title) {
  PlotOptions options;  // defaults: Recall / Precision on [0, 1]²
  options.title = title;
  options.pad = 0.02;  // a curve at precision 1 or recall 0 stays visible off the frame
  std::vector<Series> shown = curves;
  if (curves.size() == 1) {
    options.title = (title.empty() ? "" : title + kDash) + pr_metrics_text(curves.front());
  } else {
    for (Series& s : shown) s.name = (s.name.empty() ? "" : s.name + kDash) + pr_metrics_text(s);
  }
  return line_plot_svg(shown, options);
}

}  // namespace loopscan::report
