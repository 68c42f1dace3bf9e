// value_noise3 (cell cache) against its definition (eight corner hashes a call), bit for bit,
// across signs, lattice edges, -0, far coordinates and cache conflicts.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "loopscan/sim/texture_noise.hpp"

namespace loopscan {
namespace {

std::uint64_t bits(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

// Coordinates that stress floor and the lattice: random, integers and their neighbours, -0,
// beyond +-2^31, infinities and NaN.
std::vector<double> coordinates() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> near(-40.0, 40.0), far(-1e7, 1e7);
  std::vector<double> c;
  for (int i = 0; i < 3000; ++i) c.push_back(i % 3 ? near(rng) : far(rng));
  for (const double k : {0.0, 1.0, -1.0, 5.0, -7.0, 2147483647.0, -2147483648.0}) {
    c.push_back(k);
    c.push_back(std::nextafter(k, 1e300));
    c.push_back(std::nextafter(k, -1e300));
  }
  for (const double x : {-0.0, 0.5, -0.5, 2147483648.0, -2147483649.0, 1e12, -1e12, 1e300})
    c.push_back(x);
  c.push_back(std::numeric_limits<double>::infinity());
  c.push_back(std::numeric_limits<double>::quiet_NaN());
  return c;
}

double value_noise3_definition(double x, double y, double z, std::uint32_t salt) {
  const auto fade = [](double t) { return t * t * (3.0 - 2.0 * t); };
  const auto lerp = [](double a, double b, double t) { return a + (b - a) * t; };
  const std::uint32_t ix = sim::lattice(x), iy = sim::lattice(y), iz = sim::lattice(z);
  const double tx = fade(x - std::floor(x)), ty = fade(y - std::floor(y));
  const double tz = fade(z - std::floor(z));
  double layer[2];
  for (std::uint32_t k = 0; k < 2; ++k) {
    const double v00 = sim::hash_unit(salt, ix, iy, iz + k);
    const double v10 = sim::hash_unit(salt, ix + 1, iy, iz + k);
    const double v01 = sim::hash_unit(salt, ix, iy + 1, iz + k);
    const double v11 = sim::hash_unit(salt, ix + 1, iy + 1, iz + k);
    layer[k] = lerp(lerp(v00, v10, tx), lerp(v01, v11, tx), ty);
  }
  return lerp(layer[0], layer[1], tz);
}

TEST(RenderTextureNoise, CachedNoise3IsTheDefinition) {
  const std::vector<double> c = coordinates();
  std::mt19937 rng(13);
  std::uniform_int_distribution<std::size_t> pick(0, c.size() - 1);
  for (int i = 0; i < 40000; ++i) {
    const double x = c[pick(rng)] + (i % 5) * 0.02, y = c[pick(rng)], z = c[pick(rng)];
    const std::uint32_t salt = static_cast<std::uint32_t>(rng() % 3);
    ASSERT_EQ(bits(sim::value_noise3(x, y, z, salt)), bits(value_noise3_definition(x, y, z, salt)))
        << x << " " << y << " " << z;
  }
}

}  // namespace
}  // namespace loopscan
