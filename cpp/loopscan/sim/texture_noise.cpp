#include "loopscan/sim/texture_noise.hpp"

namespace loopscan::sim {
namespace {

double fade(double t) { return t * t * (3.0 - 2.0 * t); }
double lerp(double a, double b, double t) { return a + (b - a) * t; }

// Corner values of recently used lattice cells, per thread (direct-mapped): neighbouring pixels
// mostly fall into the same cells, and a lookup costs far less than four hashes.
struct Cell2 {
  std::uint32_t salt, ix, iy, used;
  double v[4];
};
thread_local Cell2 cells2[256];

// The corner values of a cell not in the cache, out of line: the hit path then needs no saved
// registers and inlines into fbm2.
__attribute__((noinline)) void fill_cell(Cell2& c, std::uint32_t salt, std::uint32_t ix,
                                         std::uint32_t iy) {
  c = Cell2{salt,
            ix,
            iy,
            1,
            {hash_unit(salt, ix, iy), hash_unit(salt, ix + 1, iy), hash_unit(salt, ix, iy + 1),
             hash_unit(salt, ix + 1, iy + 1)}};
}

inline double value_noise2_inline(double x, double y, std::uint32_t salt) {
  const double fx = std::floor(x), fy = std::floor(y);
  const std::uint32_t ix = lattice(x), iy = lattice(y);
  const double tx = fade(x - fx), ty = fade(y - fy);
  Cell2& c = cells2[(ix * 0x9e3779b1U + iy * 0x85ebca77U + salt * 0xc2b2ae3dU) >> 24];
  if (!c.used || c.salt != salt || c.ix != ix || c.iy != iy) fill_cell(c, salt, ix, iy);
  return lerp(lerp(c.v[0], c.v[1], tx), lerp(c.v[2], c.v[3], tx), ty);
}

// The same for 3D cells (eight corners): foliage is shaded with two 3D noises a pixel.
struct Cell3 {
  std::uint32_t salt, ix, iy, iz, used;
  double v[8];  // corner (dx, dy, dz) at dx + 2 dy + 4 dz
};
thread_local Cell3 cells3[256];

__attribute__((noinline)) void fill_cell3(Cell3& c, std::uint32_t salt, std::uint32_t ix,
                                          std::uint32_t iy, std::uint32_t iz) {
  c.salt = salt;
  c.ix = ix;
  c.iy = iy;
  c.iz = iz;
  c.used = 1;
  for (std::uint32_t k = 0; k < 8; ++k)
    c.v[k] = hash_unit(salt, ix + (k & 1), iy + ((k >> 1) & 1), iz + (k >> 2));
}

}  // namespace

LOOPSCAN_SIM_CLONES double value_noise2(double x, double y, std::uint32_t salt) {
  return value_noise2_inline(x, y, salt);
}

LOOPSCAN_SIM_CLONES double value_noise3(double x, double y, double z, std::uint32_t salt) {
  const double fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
  const std::uint32_t ix = lattice(x), iy = lattice(y), iz = lattice(z);
  const double tx = fade(x - fx), ty = fade(y - fy), tz = fade(z - fz);
  Cell3& c =
      cells3[(ix * 0x9e3779b1U + iy * 0x85ebca77U + iz * 0x27d4eb2fU + salt * 0xc2b2ae3dU) >> 24];
  if (!c.used || c.salt != salt || c.ix != ix || c.iy != iy || c.iz != iz)
    fill_cell3(c, salt, ix, iy, iz);
  double layer[2];
  for (int k = 0; k < 2; ++k) {
    const double* v = c.v + 4 * k;
    layer[k] = lerp(lerp(v[0], v[1], tx), lerp(v[2], v[3], tx), ty);
  }
  return lerp(layer[0], layer[1], tz);
}

LOOPSCAN_SIM_CLONES double fbm2(double x, double y, std::uint32_t salt, int octaves) {
  double sum = 0.0, norm = 0.0, amp = 1.0, freq = 1.0;
  for (int o = 0; o < octaves; ++o) {
    sum +=
        amp * value_noise2_inline(x * freq, y * freq, salt + static_cast<std::uint32_t>(o) * 7919U);
    norm += amp;
    amp *= 0.5;
    freq *= 2.0;
  }
  return norm > 0.0 ? sum / norm : 0.5;
}

}  // namespace loopscan::sim
