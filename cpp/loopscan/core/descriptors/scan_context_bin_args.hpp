#pragma once
// Internal to scan_context_bins*.cpp: what the bin kernels share.
#include <cstddef>

#include <Eigen/Core>

#include "loopscan/core/descriptors/fast_angle.hpp"

namespace loopscan::scan_context_detail {

constexpr int kMaxSectors = 128;
constexpr int kOut = -1, kFix = -2;  // bins: beyond the last ring; for the exact path

struct BinArgs {
  const double *x, *z;  // aligned axes 1 and 2, padded to whole vectors (kPad)
  std::size_t n_vec;
  const Eigen::Vector2d* centres;
  int n_centres, rings, sectors, last;  // last: boundaries tan[1..last] below 45 degrees
  double ring_inv;
  double q1, q2, offset;  // q1 = Q - 1, q2 = 2Q - 1 (Q sectors a quadrant), offset bins
  const double* tan;
  const AngleBinner* binner;
  int* bins;  // n_centres x n_vec: bin, kOut or kFix
};

constexpr int kPad = 16;  // the widest kernel's lanes

// AVX-512 intrinsics kernel, 16 points at a time (call only when simd::has_avx512()): the same
// bins as the portable kernels wherever they are not kFix (the lanes each sends to the exact
// path may differ; the exact path gives every lane its definition's bin).
void bins_avx512_intrinsics(const BinArgs& a);

}  // namespace loopscan::scan_context_detail
