#include "loopscan/core/descriptors/leading_singular.hpp"

#include "loopscan/core/descriptors/power_step.hpp"
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
// for the SSE2 baseline). Symmetric: each pair once. Four columns j at a time: four independent
// accumulators, each pair still summed in its own fixed order (the same bits as one at a time).
template <int W>
LOOPSCAN_INLINE double finish_dot(typename simd::Vec<double, W>::type acc, const double* x,
                                  const double* y, int k, int len) {
  double s = 0;
  for (int l = 0; l < simd::Vec<double, W>::kLanes; ++l) s += acc[l];
  for (; k < len; ++k) s += x[k] * y[k];
  return s;
}

template <int W>
LOOPSCAN_INLINE void gram_kernel(const double* rows, int n, int len, double* g) {
  using V = typename simd::Vec<double, W>::type;
  constexpr int kV = simd::Vec<double, W>::kLanes;
  const int body = len / kV * kV;
  for (int i = 0; i < n; ++i) {
    const double* x = rows + static_cast<std::size_t>(i) * len;
    int j = i;
    for (; j + 4 <= n; j += 4) {
      const double* y0 = rows + static_cast<std::size_t>(j) * len;
      const double *y1 = y0 + len, *y2 = y1 + len, *y3 = y2 + len;
      V a0{}, a1{}, a2{}, a3{};
      for (int k = 0; k < body; k += kV) {
        const V xv = simd::load<V>(x + k);
        a0 += xv * simd::load<V>(y0 + k);
        a1 += xv * simd::load<V>(y1 + k);
        a2 += xv * simd::load<V>(y2 + k);
        a3 += xv * simd::load<V>(y3 + k);
      }
      g[i * n + j] = g[j * n + i] = finish_dot<W>(a0, x, y0, body, len);
      g[i * n + j + 1] = g[(j + 1) * n + i] = finish_dot<W>(a1, x, y1, body, len);
      g[i * n + j + 2] = g[(j + 2) * n + i] = finish_dot<W>(a2, x, y2, body, len);
      g[i * n + j + 3] = g[(j + 3) * n + i] = finish_dot<W>(a3, x, y3, body, len);
    }
    for (; j < n; ++j) {
      const double* y = rows + static_cast<std::size_t>(j) * len;
      V acc{};
      for (int k = 0; k < body; k += kV) acc += simd::load<V>(x + k) * simd::load<V>(y + k);
      g[i * n + j] = g[j * n + i] = finish_dot<W>(acc, x, y, body, len);
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
  Eigen::VectorXd next(u.size());
  for (int it = 0; it < 1000 && !converged; ++it) {
    gram_times(gram.data(), static_cast<int>(gram.rows()), u.data(), next.data());  // gram * u
    const double n = next.norm();
    if (n == 0.0) break;
    next /= n;
    if (next.dot(u) < 0) next = -next;
    converged = (next - u).lpNorm<Eigen::Infinity>() < 1e-14;
    u.swap(next);
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
