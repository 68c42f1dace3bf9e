#pragma once
// Portable SIMD lanes (GCC/Clang vector extensions) as wide as the target's registers: 32 bytes
// when compiled for AVX, 16 (SSE2, the x86-64 baseline) otherwise. Hot loops work on several
// database places or bins at once, one per lane.
#include <type_traits>

namespace loopscan::simd {

#if defined(__AVX__)
inline constexpr int kBytes = 32;
#else
inline constexpr int kBytes = 16;
#endif

template <typename T>
struct Lanes {
  typedef T Vec __attribute__((vector_size(kBytes)));
  static constexpr int kCount = static_cast<int>(kBytes / sizeof(T));
};

}  // namespace loopscan::simd
