#include "loopscan/core/descriptors/leading_singular.hpp"

#include "loopscan/core/simd.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <vector>

#if LOOPSCAN_HAVE_AVX2_CLONES
#include <immintrin.h>
#endif

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

// acc + x * y: fused in the AVX2 clone, written out so that every build type fuses alike (the
// -O1 sanitizer build did not contract it) and the AVX-512 kernel can repeat it; the SSE2 clone
// has no FMA.
template <int W>
LOOPSCAN_INLINE typename simd::Vec<double, W>::type mul_add(
    typename simd::Vec<double, W>::type x, typename simd::Vec<double, W>::type y,
    typename simd::Vec<double, W>::type acc) {
  if constexpr (W == 32) {
    for (int l = 0; l < 4; ++l) acc[l] = __builtin_fma(x[l], y[l], acc[l]);
    return acc;
  } else {
    return acc + x * y;
  }
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
        a0 = mul_add<W>(xv, simd::load<V>(y0 + k), a0);
        a1 = mul_add<W>(xv, simd::load<V>(y1 + k), a1);
        a2 = mul_add<W>(xv, simd::load<V>(y2 + k), a2);
        a3 = mul_add<W>(xv, simd::load<V>(y3 + k), a3);
      }
      g[i * n + j] = g[j * n + i] = finish_dot<W>(a0, x, y0, body, len);
      g[i * n + j + 1] = g[(j + 1) * n + i] = finish_dot<W>(a1, x, y1, body, len);
      g[i * n + j + 2] = g[(j + 2) * n + i] = finish_dot<W>(a2, x, y2, body, len);
      g[i * n + j + 3] = g[(j + 3) * n + i] = finish_dot<W>(a3, x, y3, body, len);
    }
    for (; j < n; ++j) {
      const double* y = rows + static_cast<std::size_t>(j) * len;
      V acc{};
      for (int k = 0; k < body; k += kV) {
        acc = mul_add<W>(simd::load<V>(x + k), simd::load<V>(y + k), acc);
      }
      g[i * n + j] = g[j * n + i] = finish_dot<W>(acc, x, y, body, len);
    }
  }
}

void gram_base(const double* rows, int n, int len, double* g) { gram_kernel<16>(rows, n, len, g); }
LOOPSCAN_AVX2 void gram_avx2(const double* rows, int n, int len, double* g) {
  gram_kernel<32>(rows, n, len, g);
}

#if LOOPSCAN_HAVE_AVX2_CLONES
// gram_avx2's bits (lane l of a pair's accumulator sums k = l, l + 4, ... with fused
// multiply-adds; then 0 + lane 0 + ... + lane 3) for a tile of pairs: rows i0..i0 + 3 against
// j..j + 7. Lanes are the j, read straight from the column-major A (a column holds consecutive
// j), each load serving four rows (16 independent chains). `a`: column-major with leading
// dimension `ld`; `m`: the valid lanes.
template <bool kMasked>
LOOPSCAN_AVX512 LOOPSCAN_INLINE void gram_tile(const double* a, std::size_t ld, int n, int len,
                                               int i0, int j, __mmask8 m, double* g) {
  int row[4];
  for (int r = 0; r < 4; ++r) row[r] = i0 + r < n ? i0 + r : i0;  // spare rows: not stored
  __m512d acc[4][4];
  for (int r = 0; r < 4; ++r) {
    for (int l = 0; l < 4; ++l) acc[r][l] = _mm512_setzero_pd();
  }
  for (int k = 0; k < len; k += 4) {  // len: a multiple of 4
    for (int l = 0; l < 4; ++l) {
      const double* col = a + (k + l) * ld;
      const __m512d y = kMasked ? _mm512_maskz_loadu_pd(m, col + j) : _mm512_loadu_pd(col + j);
      for (int r = 0; r < 4; ++r) {
        acc[r][l] = _mm512_fmadd_pd(_mm512_set1_pd(col[row[r]]), y, acc[r][l]);
      }
    }
  }
  alignas(64) double out[8];
  const int lanes = n - j < 8 ? n - j : 8;
  for (int r = 0; r < 4 && i0 + r < n; ++r) {
    __m512d s = _mm512_add_pd(_mm512_setzero_pd(), acc[r][0]);
    for (int l = 1; l < 4; ++l) s = _mm512_add_pd(s, acc[r][l]);
    _mm512_store_pd(out, s);
    // A pair (j, i) below the diagonal gets the same bits (the products are exact).
    const int i = i0 + r;
    for (int l = 0; l < lanes; ++l) g[i * n + j + l] = g[(j + l) * n + i] = out[l];
  }
}

// The columns copied `ld` apart first: 512-byte columns (64 planes) all map to 8 of the 64
// L1 sets, and the tiles' reads of 128 of them missed every time (2x slower than AVX2).
LOOPSCAN_AVX512 void gram_avx512(const double* a, int n, int len, double* g) {
  const std::size_t ld = (n + 7) / 8 * 8 + 8;  // an odd number of 64-byte lines
  thread_local std::vector<double> padded;
  padded.resize(ld * len + 8);
  for (int k = 0; k < len; ++k) {
    std::copy(a + static_cast<std::size_t>(k) * n, a + static_cast<std::size_t>(k + 1) * n,
              padded.data() + k * ld);
  }
  for (int i0 = 0; i0 < n; i0 += 4) {
    int j = i0 / 8 * 8;
    for (; j + 8 <= n; j += 8) gram_tile<false>(padded.data(), ld, n, len, i0, j, 0xff, g);
    if (j < n) gram_tile<true>(padded.data(), ld, n, len, i0, j, simd::first_lanes(n - j), g);
  }
}
#endif

}  // namespace

Eigen::MatrixXd gram_matrix_for_width(const Eigen::MatrixXd& a, int width) {
  Eigen::MatrixXd g(a.rows(), a.rows());
  const int n = static_cast<int>(a.rows()), len = static_cast<int>(a.cols());
#if LOOPSCAN_HAVE_AVX2_CLONES
  // Lengths with a tail keep the AVX2 kernel: GCC vectorises its tail loop (unfused products
  // for 2 or 3 left), which this kernel does not repeat. M2DP's lengths (bins: sectors a power
  // of two from 4, times rings) have none.
  if (width >= 64 && simd::has_avx512() && len % 4 == 0) {
    gram_avx512(a.data(), n, len, g.data());
    return g;
  }
#endif
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const RowMajor rows = a;
  (width >= 32 && simd::has_avx2() ? gram_avx2 : gram_base)(rows.data(), n, len, g.data());
  return g;
}

namespace {

Eigen::MatrixXd gram_matrix(const Eigen::MatrixXd& a) { return gram_matrix_for_width(a, 64); }

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
