#pragma once
// Hash-based value noise for procedural textures. The salts come from the world's mt19937, so
// textures are deterministic in the world seed while lookups stay stateless (thread-safe).
#include <cmath>
#include <cstdint>

// The renderer's hot functions are also compiled for SSE4.2 and AVX2 and picked by the CPU (the
// build targets the x86-64 baseline): floor() becomes one instruction (~20 % of a render), and
// AVX2's three-operand encoding saves the register copies of scalar code (~8 % of the
// instructions). The bits are the same: neither target has FMA (GCC's "avx2" does not imply
// it), nothing is contracted or reordered. target_clones follow the CPU only (not
// LOOPSCAN_NO_AVX2): the tests build the library once more per clone, each compiled for that
// target only (LOOPSCAN_SIM_ONLY_TARGET, or LOOPSCAN_SIM_ONLY_DEFAULT), and check the images
// are the same on every path. ThreadSanitizer builds have no clones: their instrumented
// resolvers would run before the sanitizer's runtime starts.
#if defined(LOOPSCAN_SIM_ONLY_DEFAULT) || defined(__SANITIZE_THREAD__)
#define LOOPSCAN_SIM_CLONES
#elif defined(LOOPSCAN_SIM_ONLY_TARGET)
#define LOOPSCAN_SIM_CLONES __attribute__((target(LOOPSCAN_SIM_ONLY_TARGET)))
#elif defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__)
#define LOOPSCAN_SIM_CLONES __attribute__((target_clones("avx2", "sse4.2", "default")))
#else
#define LOOPSCAN_SIM_CLONES
#endif

namespace loopscan::sim {

inline std::uint32_t mix32(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

inline std::uint32_t hash4(std::uint32_t a, std::uint32_t b, std::uint32_t c = 0,
                           std::uint32_t d = 0) {
  std::uint32_t h = mix32(a + 0x9e3779b9U);
  h = mix32(h ^ b);
  h = mix32(h ^ (c + 0x85ebca6bU));
  return mix32(h ^ (d + 0xc2b2ae35U));
}

// Uniform in [0, 1) from 24 hash bits.
inline double hash_unit(std::uint32_t a, std::uint32_t b, std::uint32_t c = 0,
                        std::uint32_t d = 0) {
  return static_cast<double>(hash4(a, b, c, d) >> 8) * (1.0 / 16777216.0);
}

// Integer lattice coordinate of x (wraps modulo 2^32, harmless for hashing).
inline std::uint32_t lattice(double x) {
  return static_cast<std::uint32_t>(static_cast<std::int64_t>(std::floor(x)));
}

// Smooth value noise in [0, 1] with unit lattice spacing.
double value_noise2(double x, double y, std::uint32_t salt);
double value_noise3(double x, double y, double z, std::uint32_t salt);
// Fractal sum of `octaves` value-noise octaves (frequency doubling), normalised to [0, 1].
double fbm2(double x, double y, std::uint32_t salt, int octaves);

inline double smoothstep(double e0, double e1, double x) {
  if (e0 < e1) {  // outside the edge: the clamped result, without the division
    if (x <= e0) return 0.0;
    if (x >= e1) return 1.0;
  }
  double t = (x - e0) / (e1 - e0);
  t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
  return t * t * (3.0 - 2.0 * t);
}

// 1 inside [lo, hi], 0 outside, with smooth edges `edge` wide (finite texture gradients).
inline double smooth_box(double x, double lo, double hi, double edge) {
  const double h = 0.5 * edge;
  return smoothstep(lo - h, lo + h, x) * (1.0 - smoothstep(hi - h, hi + h, x));
}

}  // namespace loopscan::sim
