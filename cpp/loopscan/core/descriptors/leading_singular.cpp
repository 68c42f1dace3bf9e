#include "loopscan/core/descriptors/leading_singular.hpp"

#include "loopscan/core/simd.hpp"

#include <Eigen/SVD>
#include <cmath>

namespace loopscan {
namespace {

SingularPair jacobi_pair(const Eigen::MatrixXd& a) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
  return {svd.matrixU().col(0), svd.matrixV().col(0), svd.singularValues()(0)};
}

void make_sign_canonical(SingularPair& pair) {
  double s = pair.u.sum();
  if (s == 0.0) {
    for (Eigen::Index i = 0; i < pair.u.size() && s == 0.0; ++i) s = pair.u(i);
  }
  if (s < 0.0) {
    pair.u = -pair.u;
    pair.v = -pair.v;
  }
}

// A A^T through row dot products with a run-time AVX2 clone (Eigen's product here is compiled
// for the SSE2 baseline). Symmetric: each pair once.
template <int W>
LOOPSCAN_INLINE void gram_kernel(const double* rows, int n, int len, double* g) {
  using V = typename simd::Vec<double, W>::type;
  constexpr int kV = simd::Vec<double, W>::kLanes;
  for (int i = 0; i < n; ++i) {
    for (int j = i; j < n; ++j) {
      const double* x = rows + static_cast<std::size_t>(i) * len;
      const double* y = rows + static_cast<std::size_t>(j) * len;
      V acc{};
      int k = 0;
      for (; k + kV <= len; k += kV) acc += simd::load<V>(x + k) * simd::load<V>(y + k);
      double s = 0;
      for (int l = 0; l < kV; ++l) s += acc[l];
      for (; k < len; ++k) s += x[k] * y[k];
      g[i * n + j] = g[j * n + i] = s;
    }
  }
}

void gram_base(const double* rows, int n, int len, double* g) { gram_kernel<16>(rows, n, len, g); }
LOOPSCAN_AVX2 void gram_avx2(const double* rows, int n, int len, double* g) {
  gram_kernel<32>(rows, n, len, g);
}

Eigen::MatrixXd gram_matrix(const Eigen::MatrixXd& a) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const RowMajor rows = a;
  Eigen::MatrixXd g(a.rows(), a.rows());
  (simd::has_avx2() ? gram_avx2 : gram_base)(rows.data(), static_cast<int>(a.rows()),
                                             static_cast<int>(a.cols()), g.data());
  return g;
}

}  // namespace

SingularPair leading_singular_pair(const Eigen::MatrixXd& a, Mode mode) {
  if (mode == Mode::Reference) return jacobi_pair(a);
  SingularPair pair{Eigen::VectorXd::Zero(a.rows()), Eigen::VectorXd::Zero(a.cols()), 0.0};
  if (a.size() == 0 || a.cwiseAbs().maxCoeff() == 0.0) return pair;

  // Power iteration on the Gram matrix; for the non-negative M2DP matrices the row sums are an
  // excellent start (Perron vector) and convergence takes a few dozen steps.
  const Eigen::MatrixXd gram = gram_matrix(a);
  Eigen::VectorXd u = a.rowwise().sum();
  if (u.norm() == 0.0) u = Eigen::VectorXd::Ones(a.rows());
  u.normalize();
  bool converged = false;
  for (int it = 0; it < 1000 && !converged; ++it) {
    Eigen::VectorXd next = gram * u;
    const double n = next.norm();
    if (n == 0.0) break;
    next /= n;
    if (next.dot(u) < 0) next = -next;
    converged = (next - u).lpNorm<Eigen::Infinity>() < 1e-14;
    u = next;
  }
  if (!converged) {
    pair = jacobi_pair(a);
  } else {
    const Eigen::VectorXd atu = a.transpose() * u;
    pair = {u, atu / atu.norm(), atu.norm()};
  }
  make_sign_canonical(pair);
  return pair;
}

}  // namespace loopscan
