#pragma once
// The power iteration's matrix-vector product (leading_singular.cpp) with run-time clones.

namespace loopscan {

// out = G u for a column-major n x n matrix G: each entry summed over the columns in order,
// from +0, with unfused multiply-adds, then added to +0: the bits of Eigen's matrix-vector
// product `G * u` as compiled for the SSE2 baseline (which pins the signatures), only wider.
void gram_times(const double* g, int n, const double* u, double* out);

}  // namespace loopscan
