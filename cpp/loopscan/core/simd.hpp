#pragma once
// Portable SIMD (GCC/Clang vector extensions) with run-time dispatch: hot kernels are written
// once as templates over the vector width and instantiated for the x86-64 baseline (SSE2,
// 16 bytes) and, called only when the CPU has them, for AVX2+FMA (32 bytes). Stored data uses
// 32-byte chunks either way, so results do not depend on the CPU beyond rounding of FMA.
#include <cstring>

namespace loopscan::simd {

inline constexpr int kChunkBytes = 32;  // storage granularity: 8 floats / 4 doubles

template <typename T>
inline constexpr int kChunkLanes = static_cast<int>(kChunkBytes / sizeof(T));

template <typename T, int Bytes>
struct Vec {
  typedef T type __attribute__((vector_size(Bytes)));
  static constexpr int kLanes = static_cast<int>(Bytes / sizeof(T));
};

template <typename V>
inline V load(const void* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

template <typename V>
inline void store(void* p, const V& v) {
  std::memcpy(p, &v, sizeof v);
}

// True when the AVX2+FMA instantiations may run on this CPU.
bool has_avx2();
// True when the AVX-512 (F, DQ, VL) instantiations may run: a few kernels whose lanes are
// independent, so they give the same bits as their AVX2 instantiation, only more at a time.
bool has_avx512();

// The widest of a kernel's three clones that this machine runs (under the overrides above).
template <class Kernel>
Kernel widest(Kernel avx512, Kernel avx2, Kernel base) {
  return has_avx512() ? avx512 : has_avx2() ? avx2 : base;
}

// A mask of the first n lanes (all 32 bits from n = 32 on): the valid lanes of a partly
// filled block, or of a loop's tail (cast to the width's mask type).
inline unsigned first_lanes(int n) { return n >= 32 ? ~0u : (1u << n) - 1u; }

}  // namespace loopscan::simd

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define LOOPSCAN_AVX2 __attribute__((target("avx2,fma")))
#define LOOPSCAN_AVX512 __attribute__((target("avx2,fma,avx512f,avx512dq,avx512vl")))
#define LOOPSCAN_HAVE_AVX2_CLONES 1
#else
#define LOOPSCAN_AVX2
#define LOOPSCAN_AVX512
#define LOOPSCAN_HAVE_AVX2_CLONES 0
#endif
#define LOOPSCAN_INLINE inline __attribute__((always_inline))
