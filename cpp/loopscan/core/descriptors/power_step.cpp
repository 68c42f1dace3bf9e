// A translation unit apart from leading_singular.cpp: built with -ffp-contract=off.
#include "loopscan/core/descriptors/leading_singular.hpp"

#include "loopscan/core/simd.hpp"

namespace loopscan {
namespace {

// Eigen's column-major gemv: per block of rows and block of columns (all of them below 128),
// c = 0, then c = a * b + c for every column j of the block (pmadd without FMA: a product,
// then a sum), then res = c * alpha + res, alpha = 1, res first 0 (the product's setZero).
// Lanes are rows, so any width gives the same bits; this file is built with -ffp-contract=off
// so that nothing fuses.
template <int W>
LOOPSCAN_INLINE void times(const double* g, int n, const double* u, double* out) {
  using V = typename simd::Vec<double, W>::type;
  constexpr int kV = simd::Vec<double, W>::kLanes, kBlock = 8 * kV;  // 8 independent chains
  const int cols = n < 128 ? n : n * 8 < 32000 ? 16 : 4;             // Eigen's block_cols
  for (int i = 0; i < n; ++i) out[i] = 0.0;
  for (int j0 = 0; j0 < n; j0 += cols) {
    const int j1 = j0 + cols < n ? j0 + cols : n;
    int i = 0;
    for (; i + kBlock <= n; i += kBlock) {
      V c[8] = {};
      for (int j = j0; j < j1; ++j) {
        const double* col = g + static_cast<long>(j) * n + i;
        const double b = u[j];
        for (int k = 0; k < 8; ++k) c[k] = simd::load<V>(col + k * kV) * b + c[k];
      }
      for (int k = 0; k < 8; ++k) {
        double* r = out + i + k * kV;
        simd::store(r, c[k] * 1.0 + simd::load<V>(r));
      }
    }
    for (; i + kV <= n; i += kV) {
      V c{};
      for (int j = j0; j < j1; ++j) c = simd::load<V>(g + static_cast<long>(j) * n + i) * u[j] + c;
      simd::store(out + i, c * 1.0 + simd::load<V>(out + i));
    }
    for (; i < n; ++i) {
      double c = 0.0;
      for (int j = j0; j < j1; ++j) c = g[static_cast<long>(j) * n + i] * u[j] + c;
      out[i] = c * 1.0 + out[i];
    }
  }
}

void times_base(const double* g, int n, const double* u, double* out) { times<16>(g, n, u, out); }
LOOPSCAN_AVX2 void times_avx2(const double* g, int n, const double* u, double* out) {
  times<32>(g, n, u, out);
}
LOOPSCAN_AVX512 void times_avx512(const double* g, int n, const double* u, double* out) {
  times<64>(g, n, u, out);
}

}  // namespace

void gram_times(const double* g, int n, const double* u, double* out) {
  simd::widest(times_avx512, times_avx2, times_base)(g, n, u, out);
}

}  // namespace loopscan
