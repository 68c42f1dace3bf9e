#pragma once
// First singular vector pair of a small dense matrix (the M2DP compression step).
#include <Eigen/Core>

#include "loopscan/core/types.hpp"

namespace loopscan {

struct SingularPair {
  Eigen::VectorXd u;  // rows(A)
  Eigen::VectorXd v;  // cols(A)
  double sigma = 0.0;
};

// Reference mode: Eigen::JacobiSVD (thin U, V) exactly as the authors, the sign being whatever
// the routine returns. Default mode: power iteration on A A^T (falls back to JacobiSVD if it
// does not converge), with a canonical sign: sum(u) > 0 (first non-zero entry > 0 on a tie).
// An all-zero matrix gives zero vectors in default mode.
SingularPair leading_singular_pair(const Eigen::MatrixXd& a, Mode mode);

// A A^T as the default mode computes it, with the kernel of at most `width` bytes (64:
// AVX-512, 32: AVX2+FMA, 16: SSE2; falls back to what the CPU has). AVX-512 gives the AVX2
// bits; for tests.
Eigen::MatrixXd gram_matrix_for_width(const Eigen::MatrixXd& a, int width);

// The power iteration's step (power_step.cpp): out = G u for a column-major n x n matrix G,
// each entry summed over the columns in order, from +0, with unfused multiply-adds, then added
// to +0: the bits of Eigen's matrix-vector product `G * u` as compiled for the SSE2 baseline
// (which pins the signatures), only wider.
void gram_times(const double* g, int n, const double* u, double* out);

}  // namespace loopscan
