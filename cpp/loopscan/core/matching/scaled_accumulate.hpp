#pragma once
// out[k] += v * row[k] for k < n: a product, then a sum, never a fused multiply-add, so every
// SIMD width gives the bits of the scalar loop (the packing of Scan Context spectra).
namespace loopscan {

void scaled_accumulate(float* out, const float* row, float v, int n);

}  // namespace loopscan
