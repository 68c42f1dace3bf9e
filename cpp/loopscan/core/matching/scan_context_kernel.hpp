#pragma once
// The Scan Context matching kernel: for one query spectrum and one block of database places
// (one place per lane), the best dot product over all sector shifts, of the correlation and of
// the mirrored-order convolution, read from an inverse real DFT of the ring-summed spectra.
#include <algorithm>

#include "loopscan/core/simd.hpp"

namespace loopscan {

struct ScanContextKernelArgs {
  int rings, bins, sectors;  // bins = sectors / 2 + 1
  const void* inv_cos;       // (sectors/2 + 1) x bins, weights and 1/S folded in
  const void* inv_sin;
};

// block: [ring][bin] {re chunk, im chunk}; q: [ring][bin] re and im; best: one chunk.
template <typename T, int W>
LOOPSCAN_INLINE void scan_context_best_dot(const ScanContextKernelArgs& a, const T* qre,
                                           const T* qim, const T* block, T* best) {
  using V = typename simd::Vec<T, W>::type;
  constexpr int kV = simd::Vec<T, W>::kLanes, kL = simd::kChunkLanes<T>;
  constexpr int kMaxBins = 64;
  const int R = a.rings, K = std::min(a.bins, kMaxBins), S = a.sectors;
  const T* ic = static_cast<const T*>(a.inv_cos);
  const T* is = static_cast<const T*>(a.inv_sin);
  for (int h = 0; h < kL / kV; ++h) {
    V X[kMaxBins], Y[kMaxBins], Z[kMaxBins], U[kMaxBins];
    for (int k = 0; k < K; ++k) X[k] = Y[k] = Z[k] = U[k] = V{};
    for (int r = 0; r < R; ++r) {
      const T* d = block + static_cast<std::size_t>(r) * K * 2 * kL + h * kV;
      const T* qr = qre + r * K;
      const T* qi = qim + r * K;
      for (int k = 0; k < K; ++k) {
        const V dre = simd::load<V>(d + 2 * k * kL), dim = simd::load<V>(d + (2 * k + 1) * kL);
        X[k] += qr[k] * dre;  // sum Qre Dre
        Y[k] += qi[k] * dim;  // sum Qim Dim
        Z[k] += qi[k] * dre;  // sum Qim Dre
        U[k] += qr[k] * dim;  // sum Qre Dim
      }
    }
    // Correlation spectrum Q conj(D) = (X + Y, Z - U); convolution Q D = (X - Y, Z + U).
    for (int k = 0; k < K; ++k) {
      const V x = X[k], y = Y[k], z = Z[k], u = U[k];
      X[k] = x + y;
      Y[k] = x - y;
      Z[k] = z - u;
      U[k] = z + u;
    }
    V b = V{} - T(2);
    for (int m = 0; m <= S / 2; ++m) {
      const T* cm = ic + m * K;
      const T* sm = is + m * K;
      V ac{}, bc{}, av{}, bv{};
      for (int k = 0; k < K; ++k) {
        ac += cm[k] * X[k];
        av += cm[k] * Y[k];
        bc += sm[k] * Z[k];
        bv += sm[k] * U[k];
      }
      // Shifts m and S - m: A + B and A - B, so the larger is A + |B|.
      const V corr = ac + (bc < 0 ? -bc : bc), conv = av + (bv < 0 ? -bv : bv);
      b = b > corr ? b : corr;
      b = b > conv ? b : conv;
    }
    simd::store(best + h * kV, b);
  }
}

}  // namespace loopscan
