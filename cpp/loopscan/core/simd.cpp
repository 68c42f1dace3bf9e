#include "loopscan/core/simd.hpp"

#include <cstdlib>

namespace loopscan::simd {

bool has_avx2() {
#if LOOPSCAN_HAVE_AVX2_CLONES
  // LOOPSCAN_NO_AVX2=1 forces the baseline kernels (for testing both paths on one machine).
  static const bool yes = !std::getenv("LOOPSCAN_NO_AVX2") && __builtin_cpu_supports("avx2") &&
                          __builtin_cpu_supports("fma");
  return yes;
#else
  return false;
#endif
}

bool has_avx512() {
#if LOOPSCAN_HAVE_AVX2_CLONES
  // LOOPSCAN_NO_AVX512=1 (or LOOPSCAN_NO_AVX2=1) keeps the AVX2 (or baseline) kernels.
  static const bool yes = has_avx2() && !std::getenv("LOOPSCAN_NO_AVX512") &&
                          __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
                          __builtin_cpu_supports("avx512vl");
  return yes;
#else
  return false;
#endif
}

}  // namespace loopscan::simd
