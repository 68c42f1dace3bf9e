#pragma once
// The pair kernel behind ScanContextSpectra::best_dots (scan_context_pair_kernel.cpp), picked
// at run time for the CPU (AVX-512, AVX2+FMA or the SSE2 baseline; the same bits on the first
// two, the baseline rounds its unfused multiply-adds).
namespace loopscan {

inline constexpr int kMaxSpectraSectors = 512;

struct ScanContextPairArgs {
  int rings, sectors, m_padded;
  const float* inv_cos;  // (S/2 + 1) x m_padded, weights and 1/S folded in
  const float* inv_sin;
};

// best[c]: the best dot product of half c (structure, intensity) between the packed query q
// (and its ring-swapped copy qs) and the packed place p, over every shift and mirrored order.
void scan_context_pair_best_dots(const ScanContextPairArgs& args, const float* q, const float* qs,
                                 const float* p, float best[2]);

}  // namespace loopscan
