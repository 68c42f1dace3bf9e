#include "loopscan/report/colormap.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "loopscan/report/frame.hpp"
#include "loopscan/report/svg_text.hpp"

namespace loopscan::report {

namespace {

// Five anchor colours of matplotlib's viridis; linear in between is close enough for figures.
constexpr std::array<std::array<double, 3>, 5> kAnchors = {
    {{68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}}};

}  // namespace

std::string scale_color(double t) {
  t = std::isnan(t) ? 0.0 : std::clamp(t, 0.0, 1.0);
  const double u = t * (kAnchors.size() - 1);
  const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(u), kAnchors.size() - 2);
  const double f = u - static_cast<double>(i);
  int rgb[3];
  for (int c = 0; c < 3; ++c) {
    rgb[c] = static_cast<int>(std::lround(kAnchors[i][c] * (1 - f) + kAnchors[i + 1][c] * f));
  }
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", rgb[0], rgb[1], rgb[2]);
  return buf;
}

std::string colorbar_svg(double x, double y, double w, double h, double lo, double hi,
                         const std::string& label) {
  constexpr int kSteps = 32;
  std::string out = "<g class=\"colorbar\">\n";
  for (int k = 0; k < kSteps; ++k) {  // top step = hi
    const double t = 1.0 - (k + 0.5) / kSteps;
    out += "<rect x=\"" + svg_px(x) + "\" y=\"" + svg_px(y + h * k / kSteps) + "\" width=\"" +
           svg_px(w) + "\" height=\"" + svg_px(h / kSteps + 0.5) + "\" fill=\"" + scale_color(t) +
           "\"/>\n";
  }
  out += "<rect x=\"" + svg_px(x) + "\" y=\"" + svg_px(y) + "\" width=\"" + svg_px(w) +
         "\" height=\"" + svg_px(h) + "\" fill=\"none\" stroke=\"black\"/>\n";
  const Ticks ticks = nice_ticks(lo, hi, 4);
  for (const double v : ticks.values) {
    const double ty = y + h - (v - lo) / (hi - lo) * h;
    out += svg_line(x + w, ty, x + w + 4, ty, " stroke=\"black\"");
    out += svg_text(x + w + 7, ty, "start", format_trimmed(v, ticks.decimals), " dy=\"0.32em\"");
  }
  const double lx = x + w + 48, ly = y + h / 2;
  out += svg_text(lx, ly, "middle", label,
                  " transform=\"rotate(90 " + svg_px(lx) + " " + svg_px(ly) + ")\"");
  return out + "</g>\n";
}

}  // namespace loopscan::report
