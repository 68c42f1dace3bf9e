#pragma once
// Sub-cell refinement of a peak on a grid: the vertex of the parabola through three samples.
#include <algorithm>

namespace loopscan {

// Offset from the middle sample of the vertex of the parabola through (-1, a), (0, b), (1, c),
// within half a cell; 0 unless the parabola opens downwards.
inline double parabola_vertex(double a, double b, double c) {
  const double curvature = a - 2 * b + c;
  return curvature < 0 ? std::clamp(0.5 * (a - c) / curvature, -0.5, 0.5) : 0.0;
}

}  // namespace loopscan
