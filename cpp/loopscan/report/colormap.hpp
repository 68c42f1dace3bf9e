#pragma once
// A perceptually ordered colour scale (viridis-like: dark blue -> green -> yellow) and its
// colour bar, shared by heat maps and value-coloured lines.
#include <string>

namespace loopscan::report {

// "#rrggbb" for t in [0, 1] (clamped; NaN gives the low end).
std::string scale_color(double t);

// An SVG group: a vertical colour bar at (x, y) of size w x h, `lo` at the bottom and `hi` at
// the top, with ticks, their labels right of the bar and `label` written along it.
std::string colorbar_svg(double x, double y, double w, double h, double lo, double hi,
                         const std::string& label);

}  // namespace loopscan::report
