#include "loopscan/sim/texture_noise.hpp"

namespace loopscan::sim {
namespace {

double fade(double t) { return t * t * (3.0 - 2.0 * t); }
double lerp(double a, double b, double t) { return a + (b - a) * t; }

}  // namespace

double value_noise2(double x, double y, std::uint32_t salt) {
  const double fx = std::floor(x), fy = std::floor(y);
  const std::uint32_t ix = lattice(x), iy = lattice(y);
  const double tx = fade(x - fx), ty = fade(y - fy);
  const double v00 = hash_unit(salt, ix, iy), v10 = hash_unit(salt, ix + 1, iy);
  const double v01 = hash_unit(salt, ix, iy + 1), v11 = hash_unit(salt, ix + 1, iy + 1);
  return lerp(lerp(v00, v10, tx), lerp(v01, v11, tx), ty);
}

double value_noise3(double x, double y, double z, std::uint32_t salt) {
  const double fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
  const std::uint32_t ix = lattice(x), iy = lattice(y), iz = lattice(z);
  const double tx = fade(x - fx), ty = fade(y - fy), tz = fade(z - fz);
  double layer[2];
  for (std::uint32_t k = 0; k < 2; ++k) {
    const double v00 = hash_unit(salt, ix, iy, iz + k), v10 = hash_unit(salt, ix + 1, iy, iz + k);
    const double v01 = hash_unit(salt, ix, iy + 1, iz + k);
    const double v11 = hash_unit(salt, ix + 1, iy + 1, iz + k);
    layer[k] = lerp(lerp(v00, v10, tx), lerp(v01, v11, tx), ty);
  }
  return lerp(layer[0], layer[1], tz);
}

double fbm2(double x, double y, std::uint32_t salt, int octaves) {
  double sum = 0.0, norm = 0.0, amp = 1.0, freq = 1.0;
  for (int o = 0; o < octaves; ++o) {
    sum += amp * value_noise2(x * freq, y * freq, salt + static_cast<std::uint32_t>(o) * 7919U);
    norm += amp;
    amp *= 0.5;
    freq *= 2.0;
  }
  return norm > 0.0 ? sum / norm : 0.5;
}

}  // namespace loopscan::sim
