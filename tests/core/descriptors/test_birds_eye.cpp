// The bird's-eye place: what its key is invariant to, and its pose search against a brute-force
// search over every yaw and shift of a grid.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "loopscan/core/database/database.hpp"
#include "loopscan/core/descriptors/birds_eye_place.hpp"
#include "loopscan/core/descriptors/describe.hpp"
#include "loopscan/core/matching/birds_eye_match.hpp"
#include "loopscan/core/matching/place_matcher.hpp"
#include "loopscan/core/peak_vertex.hpp"

namespace loopscan {
namespace {

struct Point2 {
  double x, z, height;
};

// A street world on the ground plane: facades with gaps along both sides of a road that
// bends, trees at irregular spacing, parked cars, and ground points (below the structure
// height) everywhere.
std::vector<Point2> street_world(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Point2> world;
  auto road_x = [&](double z) { return 8.0 * std::sin(z / 60.0 + seed); };
  for (double z = -120; z < 120; z += 0.5) {
    for (int side : {-1, 1}) {
      const double facade = road_x(z) + side * (9.0 + 2.0 * std::sin(z / 23.0 + 3 * side + seed));
      if (std::fmod(z + 240 + 37 * seed * side, 31.0) > 6.0) {  // a gap every 31 m
        for (int k = 0; k < 4; ++k) world.push_back({facade + 0.2 * (u(rng) - 0.5), z, 2 + 8 * u(rng)});
      }
    }
  }
  for (int i = 0; i < 60; ++i) {  // trees: clusters of points
    const double z = -120 + 240 * u(rng), side = u(rng) < 0.5 ? -1 : 1;
    const double x = road_x(z) + side * (5.5 + u(rng));
    for (int k = 0; k < 40; ++k) world.push_back({x + 1.5 * (u(rng) - 0.5), z + 1.5 * (u(rng) - 0.5), 1 + 5 * u(rng)});
  }
  for (int i = 0; i < 25; ++i) {  // parked cars: short boxes
    const double z = -120 + 240 * u(rng), side = u(rng) < 0.5 ? -1 : 1;
    const double x = road_x(z) + side * 3.5;
    for (int k = 0; k < 30; ++k) world.push_back({x + 1.8 * (u(rng) - 0.5), z + 4.2 * (u(rng) - 0.5), 0.3 + 1.2 * u(rng)});
  }
  for (int i = 0; i < 8000; ++i) world.push_back({-120 + 240 * u(rng), -120 + 240 * u(rng), 0.0});
  return world;
}

// The world within 45 m of a camera at (cx, cz) with yaw psi (turning x towards z), in its
// frame: x right, y down (camera 1.7 m above the ground), z forward.
struct Scan {
  std::vector<float> x, y, z;
};
Scan scan_at(const std::vector<Point2>& world, double cx, double cz, double psi) {
  Scan s;
  const double c = std::cos(psi), sn = std::sin(psi);
  for (const Point2& p : world) {
    const double dx = p.x - cx, dz = p.z - cz;
    if (dx * dx + dz * dz > 45.0 * 45.0) continue;
    s.x.push_back(float(c * dx + sn * dz));  // R(psi)^T (p - c)
    s.z.push_back(float(-sn * dx + c * dz));
    s.y.push_back(float(1.7 - p.height));
  }
  return s;
}

BirdsEyePlace describe(const Scan& s, const BirdsEyePlaceConfig& config = {}) {
  return describe_birds_eye(s.x.data(), s.y.data(), s.z.data(), s.x.size(), config);
}

double angle_error(double a, double b) { return std::abs(std::remainder(a - b, 2 * M_PI)); }

// The correlation of the query with the place turned by yaw and shifted by whole cells,
// summed over every query cell with the place image sampled where that cell comes from.
// `weight` (of a cell's distance from the keyframe) weighs both the query's cells and the
// turned place's.
double oracle_correlation(
    const BirdsEyePlace& q, const BirdsEyePlace& d, double yaw, int dx, int dz,
    const BirdsEyePlaceConfig& config,
    const std::function<double(double)>& weight = [](double) { return 1.0; }) {
  const int n = q.side;
  auto place_at = [&](double x, double z) {  // bilinear over cell centres, zero outside
    const double fc = (x + config.range_m) / config.cell_m - 0.5;
    const double fr = (z + config.range_m) / config.cell_m - 0.5;
    double sum = 0;
    for (int r = int(std::floor(fr)); r <= int(std::floor(fr)) + 1; ++r) {
      for (int c = int(std::floor(fc)); c <= int(std::floor(fc)) + 1; ++c) {
        if (r < 0 || r >= n || c < 0 || c >= n) continue;
        sum += (1 - std::abs(fr - r)) * (1 - std::abs(fc - c)) * d.image[r * n + c];
      }
    }
    return sum;
  };
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  double dot = 0, qq = 0, dd = 0;
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      const double x = (c + 0.5) * config.cell_m - config.range_m;
      const double z = (r + 0.5) * config.cell_m - config.range_m;
      // The place at R^T p.
      const double turned = weight(std::hypot(x, z)) * place_at(cy * x + sy * z, -sy * x + cy * z);
      dd += turned * turned;
      const double qv = weight(std::hypot(x, z)) * q.image[r * n + c];
      qq += qv * qv;
      const int sr = r - dz, sc = c - dx;  // the turned place's cell that lands on (r, c)
      if (sr < 0 || sr >= n || sc < 0 || sc >= n) continue;
      const double xs = (sc + 0.5) * config.cell_m - config.range_m;
      const double zs = (sr + 0.5) * config.cell_m - config.range_m;
      dot += qv * weight(std::hypot(xs, zs)) * place_at(cy * xs + sy * zs, -sy * xs + cy * zs);
    }
  }
  return qq > 0 && dd > 0 ? dot / std::sqrt(qq * dd) : 0.0;
}

TEST(PeakVertex, RecoversASampledParabolasVertex) {
  for (double vertex : {-0.45, -0.2, 0.0, 0.1, 0.37}) {
    const auto f = [&](double x) { return 3.0 - 2.0 * (x - vertex) * (x - vertex); };
    EXPECT_NEAR(parabola_vertex(f(-1), f(0), f(1)), vertex, 1e-12);
  }
  EXPECT_EQ(parabola_vertex(0.0, 1.0, 0.99), 0.5 * (0.0 - 0.99) / (0.0 - 2.0 + 0.99));
  EXPECT_EQ(parabola_vertex(0.0, 1.0, 1.9), 0.5);   // vertex 9.5 cells out: clamped
  EXPECT_EQ(parabola_vertex(1.0, 1.0, 1.0), 0.0);   // flat
  EXPECT_EQ(parabola_vertex(1.0, 0.0, 1.0), 0.0);   // a valley, not a peak
}

TEST(BirdsEyePlace, SizeAndEmptyPlace) {
  const BirdsEyePlaceConfig config;
  const BirdsEyePlace empty = describe_birds_eye(nullptr, nullptr, nullptr, 0, config);
  EXPECT_EQ(empty.side, 60);
  EXPECT_EQ(empty.bytes(), 60u * 60u + 24u * 60u);
  EXPECT_LE(empty.bytes(), 9600u);  // no larger than one full Scan Context
  for (auto v : empty.image) ASSERT_EQ(v, 0);
  for (auto v : empty.key) ASSERT_EQ(v, 0);
  EXPECT_DOUBLE_EQ(match_keys(empty, empty, config.angles).distance, 1.0);
  const BirdsEyePose pose = birds_eye_pose(empty, empty, 0.0, config);
  EXPECT_EQ(pose.score, 0.0);
}

TEST(BirdsEyePlace, GroundAndUnusablePointsLeaveNoTrace) {
  const Scan s = scan_at(street_world(1), 0, 0, 0);
  Scan with = s;
  for (int i = 0; i < 500; ++i) {  // ground below the structure height, and NaN heights
    with.x.push_back(float(i % 50) - 25.f);
    with.z.push_back(float(i / 50) - 5.f);
    with.y.push_back(i % 7 == 0 ? NAN : 1.7f);
  }
  const BirdsEyePlace a = describe(s), b = describe(with);
  EXPECT_EQ(a.image, b.image);
  EXPECT_EQ(a.key, b.key);
}

// Two cells near the keyframe (full weight): one point 8 m up, nine points 2 m up.
TEST(BirdsEyePlace, CellsHoldDensityOrHeight) {
  std::vector<float> x = {0.5f}, y = {-8.f}, z = {5.5f};
  for (int i = 0; i < 9; ++i) {
    x.push_back(-4.5f);
    y.push_back(-2.f);
    z.push_back(2.5f);
  }
  BirdsEyePlaceConfig config;  // min_height_m -1: heights over it are 9 and 3
  const int n = image_side(config), high = (30 + 5) * n + 30, low = (30 + 2) * n + 25;
  const BirdsEyePlace density = describe_birds_eye(x.data(), y.data(), z.data(), x.size(), config);
  EXPECT_EQ(density.image[low], 255);
  EXPECT_EQ(density.image[high], 61);  // log(1 + 1/2) / log(1 + 9/2) of 255: 60.65
  config.cell = BirdsEyeCell::Height;
  const BirdsEyePlace height = describe_birds_eye(x.data(), y.data(), z.data(), x.size(), config);
  EXPECT_EQ(height.image[high], 255);
  EXPECT_EQ(height.image[low], 85);  // 3 / 9
  int lit = 0;
  for (auto v : height.image) lit += v != 0;
  EXPECT_EQ(lit, 2);
}

TEST(BirdsEyePlace, InvalidConfigurationsAreRefused) {
  BirdsEyePlaceConfig c;
  c.cell_m = 0;
  EXPECT_THROW(validate(c), std::invalid_argument);
  EXPECT_THROW(BirdsEyeDescriber{c}, std::invalid_argument);  // before sizing its image
  c = {};
  c.taper_end_m = c.taper_start_m;
  EXPECT_THROW(validate(c), std::invalid_argument);
  c = {};
  c.spectrum_size = 32;  // smaller than the 60-cell image
  EXPECT_THROW(validate(c), std::invalid_argument);
  c = {};
  c.max_frequency = 63.5;  // samples reach past the spectrum's Nyquist frequency (64)
  EXPECT_THROW(validate(c), std::invalid_argument);
  c.max_frequency = 63;  // the highest allowed: describes
  const Scan s = scan_at(street_world(1), 0, 0, 0);
  EXPECT_EQ(describe(s, c).key.size(), std::size_t(c.rings * c.angles));
  c = {};
  const BirdsEyePlace a = describe(s);
  BirdsEyePlace cut = a;
  cut.key.pop_back();
  EXPECT_THROW(match_keys(a, cut, c.angles), std::invalid_argument);
  cut = a;
  cut.image.pop_back();
  EXPECT_THROW(birds_eye_pose(a, cut, 0.0, c), std::invalid_argument);
}

// The place straight from its definition, in double precision: each cell's log(1 + count / 2) or
// height times its taper weight, scaled to 255 at the top cell; the key is log(1 + |DFT|) of
// the image zero-padded to spectrum_size, by the sum over every cell, sampled bilinearly on
// the polar grid, ring means removed and scaled to 127 at the largest magnitude.
struct OraclePlace {
  std::vector<double> image, key;
};
OraclePlace oracle_place(const Scan& s, const BirdsEyePlaceConfig& c) {
  const int n = image_side(c), N = c.spectrum_size;
  std::vector<double> image(std::size_t(n) * n, 0.0);
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    const double height = -double(s.y[i]);
    const double fc = (double(s.x[i]) + c.range_m) / c.cell_m;
    const double fr = (double(s.z[i]) + c.range_m) / c.cell_m;
    if (!(height > c.min_height_m) || fc < 0 || fc >= n || fr < 0 || fr >= n) continue;
    double& v = image[std::size_t(fr) * n + std::size_t(fc)];
    v = c.cell == BirdsEyeCell::Density ? v + 1 : std::max(v, height - c.min_height_m);
  }
  for (int r = 0; r < n; ++r) {
    for (int col = 0; col < n; ++col) {
      double& v = image[std::size_t(r) * n + col];
      if (c.cell == BirdsEyeCell::Density) v = std::log1p(v / 2);
      const double d =
          std::hypot((col + 0.5) * c.cell_m - c.range_m, (r + 0.5) * c.cell_m - c.range_m);
      const double w =
          std::clamp((c.taper_end_m - d) / (c.taper_end_m - c.taper_start_m), 0.0, 1.0);
      v *= std::pow(std::sin(w * M_PI / 2), 2);
    }
  }
  const double top = *std::max_element(image.begin(), image.end());
  OraclePlace o;
  for (double v : image) o.image.push_back(255.0 * v / top);
  auto log_magnitude = [&](int u, int v) {
    std::complex<double> f = 0;
    for (int r = 0; r < n; ++r) {
      for (int col = 0; col < n; ++col) {
        const double value = image[std::size_t(r) * n + col];
        if (value != 0) f += value * std::polar(1.0, -2 * M_PI * double((u * r + v * col) % N) / N);
      }
    }
    return std::log1p(std::abs(f));
  };
  std::map<std::pair<int, int>, double> bins;  // each bin once
  auto bin = [&](int u, int v) {
    const auto it = bins.find({u, v});
    return it != bins.end() ? it->second : bins[{u, v}] = log_magnitude(u, v);
  };
  double peak = 0;
  for (int ring = 0; ring < c.rings; ++ring) {
    const double rho = c.min_frequency + ring * (c.max_frequency - c.min_frequency) / (c.rings - 1);
    std::vector<double> values;
    for (int a = 0; a < c.angles; ++a) {
      const double u = rho * std::sin(a * M_PI / c.angles), v = rho * std::cos(a * M_PI / c.angles);
      const int u0 = int(std::floor(u)), v0 = int(std::floor(v));
      const double fu = u - u0, fv = v - v0;
      values.push_back((1 - fu) * ((1 - fv) * bin(u0, v0) + fv * bin(u0, v0 + 1)) +
                       fu * ((1 - fv) * bin(u0 + 1, v0) + fv * bin(u0 + 1, v0 + 1)));
    }
    const double mean = std::accumulate(values.begin(), values.end(), 0.0) / c.angles;
    for (double v : values) {
      o.key.push_back(v - mean);
      peak = std::max(peak, std::abs(v - mean));
    }
  }
  for (double& v : o.key) v *= 127.0 / peak;
  return o;
}

// The describer's vector kernels and single-precision transform against the definition: every
// image cell and key value within rounding of the oracle's (one step of the quantisation), on
// places of both cell kinds and another cell size.
TEST(BirdsEyePlace, DescriptionEqualsTheDefinitionWithinRounding) {
  const auto world = street_world(5);
  BirdsEyePlaceConfig coarse;
  coarse.cell_m = 1.5;
  coarse.range_m = 27;
  coarse.spectrum_size = 64;
  coarse.max_frequency = 20;
  BirdsEyePlaceConfig height;
  height.cell = BirdsEyeCell::Height;
  for (const BirdsEyePlaceConfig& config : {BirdsEyePlaceConfig{}, height, coarse}) {
    for (const auto& [cx, cz, psi] : {std::tuple{0.0, 0.0, 0.0}, std::tuple{2.5, -30.0, 2.2}}) {
      const Scan s = scan_at(world, cx, cz, psi);
      const BirdsEyePlace place = describe(s, config);
      const OraclePlace expected = oracle_place(s, config);
      ASSERT_EQ(place.image.size(), expected.image.size());
      ASSERT_EQ(place.key.size(), expected.key.size());
      int off_by_one = 0;
      for (std::size_t i = 0; i < place.image.size(); ++i) {
        ASSERT_LE(std::abs(place.image[i] - expected.image[i]), 0.5 + 1e-3) << "cell " << i;
      }
      for (std::size_t i = 0; i < place.key.size(); ++i) {
        const double error = std::abs(place.key[i] - expected.key[i]);
        ASSERT_LE(error, 1.0) << "key " << i;
        off_by_one += error > 0.5 + 1e-3;
      }
      EXPECT_LE(off_by_one, int(place.key.size()) / 100);  // rounding, not a drift
    }
  }
}

// A turn of the place shifts its key: the key's yaw is the turn modulo pi, and a translation
// barely changes the key.
TEST(BirdsEyePlace, KeyGivesTheYawAndIgnoresTranslation) {
  const auto world = street_world(3);
  const BirdsEyePlaceConfig config;
  const double step = M_PI / config.angles;
  const BirdsEyePlace place = describe(scan_at(world, 0, 0, 0));
  for (int k = 0; k < 12; ++k) {
    const double psi = -M_PI + k * 2 * M_PI / 12 + 0.01;
    const BirdsEyePlace query = describe(scan_at(world, 0, 0, psi));
    const BirdsEyeKeyMatch m = match_keys(query, place, config.angles);
    // The place's yaw in the query frame is -psi (see BirdsEyePose), modulo pi.
    const double err = std::min(angle_error(m.yaw_rad, -psi), angle_error(m.yaw_rad, -psi + M_PI));
    EXPECT_LE(err, 1.01 * step) << "psi " << psi;
    EXPECT_LT(m.distance, 0.1) << "psi " << psi;
  }
  const BirdsEyePlace moved = describe(scan_at(world, 3.5, 4.0, 0));
  const BirdsEyePlace elsewhere = describe(scan_at(street_world(11), 0, 0, 0));
  EXPECT_LT(match_keys(moved, place, config.angles).distance,
            0.5 * match_keys(elsewhere, place, config.angles).distance);
}

// The key correlation at one shift, straight from the definition: q[a] against d[a - shift].
double key_correlation(const BirdsEyePlace& q, const BirdsEyePlace& d, int angles, int shift) {
  double dot = 0, qq = 0, dd = 0;
  for (std::size_t i = 0; i < q.key.size(); ++i) {
    const std::size_t ring = i / angles, a = i % angles;
    dot += double(q.key[i]) * d.key[ring * angles + (a + angles - shift) % angles];
    qq += double(q.key[i]) * q.key[i];
    dd += double(d.key[i]) * d.key[i];
  }
  return dot / std::sqrt(qq * dd);
}

// Keys exactly and through their spectra: the same best correlation (the spectral path may
// pick another shift only where the two tie within float rounding), against brute force.
TEST(BirdsEyeMatch, KeySpectraAgreeWithTheDefinition) {
  const BirdsEyePlaceConfig config;
  std::vector<std::pair<BirdsEyePlace, int>> places;  // with its angle count
  for (unsigned w = 0; w < 3; ++w) {
    const auto world = street_world(40 + w);
    for (int k = 0; k < 4; ++k) {
      places.push_back({describe(scan_at(world, 2.0 * k, 5.0 * k, 0.7 * k)), config.angles});
    }
  }
  std::mt19937 rng(4);  // and keys of noise, with an even and an odd angle count
  for (int angles : {60, 45}) {
    for (int k = 0; k < 2; ++k) {
      BirdsEyePlace p;
      p.key.resize(std::size_t(7) * angles);
      for (auto& v : p.key) v = std::int8_t(int(rng() % 255) - 127);
      places.push_back({p, angles});
    }
  }
  int pairs = 0;
  for (const auto& [q, angles] : places) {
    for (const auto& [d, d_angles] : places) {
      if (q.key.size() != d.key.size() || angles != d_angles) continue;
      double best = -2;
      for (int s = 0; s < angles; ++s) best = std::max(best, key_correlation(q, d, angles, s));
      const BirdsEyeKeyMatch exact = match_keys(q, d, angles);
      const BirdsEyeKeyMatch fast = match_key_spectra(key_spectrum(q, angles), key_spectrum(d, angles));
      EXPECT_NEAR(exact.distance, 1 - best, 1e-12);
      EXPECT_NEAR(fast.distance, exact.distance, 1e-5);
      const int shift = int(std::lround(fast.yaw_rad * angles / M_PI)) % angles;
      EXPECT_NEAR(key_correlation(q, d, angles, shift), best, 1e-5);
      ++pairs;
    }
  }
  EXPECT_EQ(pairs, 12 * 12 + 2 * 2 + 2 * 2);
}

// The bfloat16 copy the key scan's bound reads: real parts then imaginary parts, each the
// float's upper 16 bits rounded to nearest, so within 2^-8 of it relatively (what the bound is
// widened by).
TEST(BirdsEyeMatch, RoundedSpectrumIsWithinItsRoundingBound) {
  const BirdsEyePlaceConfig config;
  const BirdsEyeKeySpectrum s =
      key_spectrum(describe(scan_at(street_world(8), 1, 2, 0.3)), config.angles);
  const std::vector<std::uint16_t>& rounded = s.rounded;
  ASSERT_EQ(rounded.size(), s.re.size() + s.im.size());
  int inexact = 0;
  for (std::size_t i = 0; i < rounded.size(); ++i) {
    const float exact = i < s.re.size() ? s.re[i] : s.im[i - s.re.size()];
    const std::uint32_t bits = std::uint32_t(rounded[i]) << 16;
    float value;
    std::memcpy(&value, &bits, sizeof value);
    ASSERT_LE(std::abs(value - exact), std::ldexp(std::abs(exact), -8)) << i;
    inexact += value != exact;
  }
  EXPECT_GT(inexact, int(rounded.size()) / 2);  // it does round
}

// The bound-pruned search for the nearest keys returns exactly the head of every eligible
// place's (distance, place) sorted: duplicated places (ties), places turned by any yaw, noise.
TEST(BirdsEyeMatch, NearestKeysAreTheHeadOfTheSortedKeyDistances) {
  const BirdsEyePlaceConfig config;
  std::vector<BirdsEyeKeySpectrum> spectra;
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(-1, 1);
  for (unsigned w = 0; w < 3; ++w) {
    const auto world = street_world(50 + w);
    for (int k = 0; k < 30; ++k) {
      const BirdsEyePlace p = describe(scan_at(world, 3 * u(rng), 50 * u(rng), M_PI * u(rng)));
      spectra.push_back(key_spectrum(p, config.angles));
      if (k % 7 == 0) spectra.push_back(spectra.back());  // a tie
    }
  }
  BirdsEyePlace empty;  // a place without structure: distance 1 to everything
  empty.key.assign(std::size_t(spectra[0].rings) * config.angles, 0);
  spectra.push_back(key_spectrum(empty, config.angles));
  // Each place's spectrum with its bfloat16 copy for the bound, or without it.
  bool use_rounded = false;
  const auto at = [&](std::size_t i) {
    BirdsEyeKeySpectrumView v = view(spectra[i]);
    if (!use_rounded) v.rounded = nullptr;
    return v;
  };
  for (std::size_t q = 0; q < spectra.size(); q += 11) {
    use_rounded = q % 2 == 1;
    const auto eligible = [&](std::size_t i) { return i % 5 != q % 5; };
    std::vector<std::pair<double, std::size_t>> all;
    for (std::size_t i = 0; i < spectra.size(); ++i) {
      if (eligible(i)) all.emplace_back(match_key_spectra(spectra[q], spectra[i]).distance, i);
    }
    std::sort(all.begin(), all.end());
    for (std::size_t count : {std::size_t(1), std::size_t(10), all.size() + 3}) {
      const auto nearest = nearest_keys(view(spectra[q]), spectra.size(), eligible, at, count);
      ASSERT_EQ(nearest.size(), std::min(count, all.size()));
      for (std::size_t j = 0; j < nearest.size(); ++j)
        EXPECT_EQ(nearest[j], all[j]) << q << " " << j;
    }
  }
}

TEST(BirdsEyeMatch, CorrelationEqualsTheOracle) {
  const auto world = street_world(5);
  const BirdsEyePlaceConfig config;
  const BirdsEyePlace q = describe(scan_at(world, 1.0, 2.0, 0.3));
  const BirdsEyePlace d = describe(scan_at(world, -2.0, 0.0, 2.9));
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> yaw(-M_PI, M_PI);
  const int m = 4;
  for (int trial = 0; trial < 4; ++trial) {
    const double y = yaw(rng);
    const std::vector<double> corr = birds_eye_correlation(q, d, y, config, m);
    ASSERT_EQ(corr.size(), std::size_t((2 * m + 1) * (2 * m + 1)));
    for (int dz = -m; dz <= m; ++dz) {
      for (int dx = -m; dx <= m; ++dx) {
        const double expected = oracle_correlation(q, d, y, dx, dz, config);
        // Sums of about a thousand products in float.
        EXPECT_NEAR(corr[(dz + m) * (2 * m + 1) + dx + m], expected, 1e-5 * expected + 1e-9);
      }
    }
  }
}

// Revisits from any direction, up to 4 m aside and 6 m along: the pose search, which tries
// only the key's yaw and the yaw plus pi, finds the best pose of a brute-force search over
// every yaw (a key angle apart) and every whole-cell shift, and that pose is the truth.
// With the default windows (the pose searched on the stored images) and with a flat stored
// window whose pose is searched on near-weighed images.
TEST(BirdsEyeMatch, PoseSearchMatchesBruteForceAndTheTruth) {
  BirdsEyePlaceConfig flat;
  flat.taper_start_m = 28;
  BirdsEyeSearchConfig near;
  near.pose_window_start_m = 10;
  near.pose_window_end_m = 30;
  for (const auto& [config, base] :
       {std::pair{BirdsEyePlaceConfig{}, BirdsEyeSearchConfig{}}, std::pair{flat, near}}) {
    BirdsEyeSearchConfig search = base;
    search.max_shift_m = 8.0;
    const int m = 8;
    const double step = M_PI / config.angles;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int trial = 0; trial < 6; ++trial) {
      const auto world = street_world(20 + trial);
      const double psi_p = M_PI * u(rng), psi_q = M_PI * u(rng);
      const double pz = 10 * u(rng), qx = 4 * u(rng), qz = pz + 6 * u(rng);
      const BirdsEyePlace place = describe(scan_at(world, 0, pz, psi_p), config);
      const BirdsEyePlace query = describe(scan_at(world, qx, qz, psi_q), config);
      const BirdsEyeKeyMatch key = match_keys(query, place, config.angles);
      const BirdsEyePose found = birds_eye_pose(query, place, key.yaw_rad, config, search);
      // The pose maximises the weighed images' correlation; the score is the stored images' there.
      double best = -1, best_yaw = 0, searched = -1;  // over every yaw; over the searched two
      int best_dx = 0, best_dz = 0;
      for (int k = 0; k < 2 * config.angles + 2; ++k) {
        const bool key_yaw = k >= 2 * config.angles;
        const double yaw = key_yaw ? key.yaw_rad + (k % 2) * M_PI : k * step;
        const std::vector<double> corr =
            birds_eye_pose_correlation(query, place, yaw, config, search, m);
        for (int i = 0; i < int(corr.size()); ++i) {
          if (key_yaw) searched = std::max(searched, corr[i]);
          if (!key_yaw && corr[i] > best) {
            best = corr[i], best_yaw = yaw;
            best_dx = i % (2 * m + 1) - m, best_dz = i / (2 * m + 1) - m;
          }
        }
      }
      SCOPED_TRACE(testing::Message() << "taper from " << config.taper_start_m << ", trial "
                                      << trial << " psi_p " << psi_p << " psi_q " << psi_q);
      // The best whole-cell pose of the two yaws searched; within 1 % of the best over every yaw
      // (the stored images' key gives the yaw to a key angle).
      EXPECT_GE(found.fit, searched - 1e-9);
      EXPECT_GE(found.fit, 0.99 * best);
      const int fx = int(std::lround(found.x_m / config.cell_m)),
                fz = int(std::lround(found.z_m / config.cell_m));
      const std::vector<double> stored =
          birds_eye_correlation(query, place, found.yaw_rad, config, m);
      EXPECT_NEAR(found.score, stored[(fz + m) * (2 * m + 1) + fx + m], 1e-12);
      EXPECT_LE(angle_error(found.yaw_rad, best_yaw), 1.01 * step);
      EXPECT_LE(std::abs(found.x_m - best_dx * config.cell_m), 0.5 * config.cell_m + 1e-9);
      EXPECT_LE(std::abs(found.z_m - best_dz * config.cell_m), 0.5 * config.cell_m + 1e-9);
      // The truth: place point p_d lies at R(psi_p - psi_q) p_d + R(psi_q)^T (c_p - c_q).
      const double c = std::cos(psi_q), s = std::sin(psi_q);
      const double tx = c * (0 - qx) + s * (pz - qz), tz = -s * (0 - qx) + c * (pz - qz);
      EXPECT_LE(angle_error(found.yaw_rad, psi_p - psi_q), 2.01 * step);
      EXPECT_LE(std::hypot(found.x_m - tx, found.z_m - tz), 1.0);
      EXPECT_GT(found.score, 0.5);
    }
  }
}

// The correlation the pose search maximises against a direct sum over the weighed images; a
// window beyond the image weighs nothing, and the search's fit is then its score.
TEST(BirdsEyeMatch, PoseCorrelationEqualsTheWeighedOracle) {
  const BirdsEyePlaceConfig config;
  BirdsEyeSearchConfig search;
  search.pose_window_start_m = 10;
  search.pose_window_end_m = 30;
  const auto world = street_world(8);
  const BirdsEyePlace q = describe(scan_at(world, 0.5, 1.0, 0.2));
  const BirdsEyePlace d = describe(scan_at(world, -1.0, 3.0, 2.8));
  const auto weight = [&](double dist) {
    return birds_eye_window_weight(dist, search.pose_window_start_m, search.pose_window_end_m);
  };
  const int m = 3;
  for (double y : {-2.1, 0.4, 2.9}) {
    const std::vector<double> corr = birds_eye_pose_correlation(q, d, y, config, search, m);
    const std::vector<double> stored = birds_eye_correlation(q, d, y, config, m);
    ASSERT_EQ(corr.size(), std::size_t((2 * m + 1) * (2 * m + 1)));
    int differ = 0;
    for (int dz = -m; dz <= m; ++dz) {
      for (int dx = -m; dx <= m; ++dx) {
        const std::size_t i = std::size_t((dz + m) * (2 * m + 1) + dx + m);
        const double expected = oracle_correlation(q, d, y, dx, dz, config, weight);
        EXPECT_NEAR(corr[i], expected, 1e-5 * expected + 1e-9);
        differ += std::abs(corr[i] - stored[i]) > 1e-3;
      }
    }
    EXPECT_GT(differ, 0);  // the window weighs something
  }
  // The default window starts where the image ends: nothing weighed, fit and score alike.
  const BirdsEyeSearchConfig beyond;
  ASSERT_GE(beyond.pose_window_start_m, config.taper_end_m);
  EXPECT_EQ(birds_eye_pose_correlation(q, d, 0.4, config, beyond, m),
            birds_eye_correlation(q, d, 0.4, config, m));
  const double yaw = match_keys(q, d, config.angles).yaw_rad;
  const BirdsEyePose a = birds_eye_pose(q, d, yaw, config, beyond);
  EXPECT_GT(a.score, 0.3);
  EXPECT_EQ(a.fit, a.score);
  const BirdsEyePose b = birds_eye_pose(q, d, yaw, config, search);
  EXPECT_NE(b.fit, b.score);
  BirdsEyeSearchConfig bad = search;
  bad.pose_window_end_m = bad.pose_window_start_m;
  EXPECT_THROW(birds_eye_pose_correlation(q, d, 0.4, config, bad, m), std::invalid_argument);
}

// The default search (coarse cells, then full resolution around the best coarse peaks) against
// every shift at full resolution, on revisits and on other places: never a better score than
// the full search (its windows are a subset, summed in the same order), and on revisits the
// same pose.
TEST(BirdsEyeMatch, CoarseToFineSearchFindsTheFullSearchsPose) {
  const BirdsEyePlaceConfig config;
  BirdsEyeSearchConfig full;
  full.coarse_cells = 1;
  const BirdsEyeSearchConfig coarse;
  ASSERT_GT(coarse.coarse_cells, 1);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  int revisits = 0, same = 0, others = 0;
  for (int trial = 0; trial < 24; ++trial) {
    const auto world = street_world(60 + trial / 2);
    const auto other = street_world(90 + trial);
    const double pz = 20 * u(rng);
    const BirdsEyePlace place = describe(scan_at(world, 3 * u(rng), pz, M_PI * u(rng)));
    const BirdsEyePlace query = describe(scan_at(world, 3 * u(rng), pz + 8 * u(rng), M_PI * u(rng)));
    const BirdsEyePlace stranger = describe(scan_at(other, 0, 0, M_PI * u(rng)));
    for (const BirdsEyePlace* d : {&place, &stranger}) {
      const double yaw = match_keys(query, *d, config.angles).yaw_rad;
      const BirdsEyePose a = birds_eye_pose(query, *d, yaw, config, full);
      const BirdsEyePose b = birds_eye_pose(query, *d, yaw, config, coarse);
      EXPECT_LE(b.fit, a.fit + 1e-12) << trial;
      if (d == &stranger) {
        ++others;
        continue;
      }
      ++revisits;
      if (std::abs(a.fit - b.fit) < 1e-12 && std::abs(a.x_m - b.x_m) < 1e-9 &&
          std::abs(a.z_m - b.z_m) < 1e-9 && std::abs(a.yaw_rad - b.yaw_rad) < 1e-12) {
        ++same;
      }
    }
  }
  EXPECT_EQ(revisits, 24);
  EXPECT_EQ(others, 24);
  EXPECT_GE(same, 23) << "coarse to fine missed the full search's pose on " << revisits - same
                      << " of " << revisits << " revisits";
}

// Places along two streets, each seen from a random lane and direction: the method's
// recognition path (signature, matcher, database) and its brute-force oracles.
struct Places {
  std::vector<BirdsEyePlace> places;
  std::vector<Signature> signatures;
};
Places street_places(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  const std::vector<Point2> worlds[2] = {street_world(31), street_world(32)};
  Places out;
  for (int i = 0; i < n; ++i) {
    const BirdsEyePlace p =
        describe(scan_at(worlds[i % 2], 3 * u(rng), 60 * u(rng), M_PI * u(rng)));
    out.places.push_back(p);
    out.signatures.push_back(birds_eye_signature(p));
  }
  return out;
}

double image_distance(const BirdsEyePlace& q, const BirdsEyePlace& d) {
  const BirdsEyePlaceConfig config;
  return birds_eye_distance(
      birds_eye_pose(q, d, match_keys(q, d, config.angles).yaw_rad, config, {}));
}

TEST(BirdsEyeMethod, SignatureHoldsThePlaceAndRefusesOthers) {
  const BirdsEyePlaceConfig config;
  const Scan s = scan_at(street_world(5), 1.0, 3.0, 0.4);
  Cloud cloud;
  for (std::size_t i = 0; i < s.x.size(); ++i) cloud.push_back({Eigen::Vector3d(s.x[i], s.y[i], s.z[i]), 0.f});
  const Signature sig = loopscan::describe(Method::BirdsEye, cloud, DescriptorConfig::for_mode(Mode::Default));
  ASSERT_EQ(sig.rows(), rows_per_place(Method::BirdsEye));
  ASSERT_EQ(sig.cols(), signature_columns(Method::BirdsEye));
  const BirdsEyePlace direct = describe(s), back = birds_eye_place(sig, config);
  EXPECT_EQ(back.image, direct.image);
  EXPECT_EQ(back.key, direct.key);
  EXPECT_EQ(method_name(parse_method("bev")), "bev");
  Signature bad = sig;
  bad(0, 5) = 256;
  EXPECT_THROW(birds_eye_place(bad, config), std::invalid_argument);
  bad = sig;
  bad(0, sig.cols() - 1) = 0.5;
  EXPECT_THROW(birds_eye_place(bad, config), std::invalid_argument);
  EXPECT_THROW(birds_eye_place(Signature(1, 10), config), std::invalid_argument);
  cloud[0].p.x() = std::nan("");
  EXPECT_THROW(loopscan::describe(Method::BirdsEye, cloud, {}), std::invalid_argument);
}

TEST(BirdsEyeMethod, MatcherRowsAreKeyDistancesAndEvaluationRowsSearchTheAllowedFinalists) {
  const Places p = street_places(40, 3);
  BirdsEyeSearchConfig search;
  search.finalists = 5;
  const auto matcher = make_birds_eye_matcher({}, search);
  for (const Signature& s : p.signatures) matcher->add(s);
  ASSERT_EQ(matcher->components(), 1);
  const int angles = BirdsEyePlaceConfig{}.angles;
  for (int q : {0, 17, 39}) {
    Eigen::MatrixXd rows;
    matcher->distances(p.signatures[q], rows);
    ASSERT_EQ(rows.cols(), 40);
    std::vector<std::pair<double, int>> allowed;
    for (int j = 0; j < 40; ++j) {
      const double key = match_keys(p.places[q], p.places[j], angles).distance;
      EXPECT_NEAR(rows(0, j), key, 1e-5);
      if (std::abs(q - j) >= 10) allowed.emplace_back(rows(0, j), j);
    }
    std::sort(allowed.begin(), allowed.end());
    matcher->rows(p.signatures[q], q, 10, rows);
    for (int j = 0; j < 40; ++j) {
      const bool finalist =
          std::find_if(allowed.begin(), allowed.begin() + 5,
                       [j](const auto& a) { return a.second == j; }) != allowed.begin() + 5;
      if (finalist) {
        EXPECT_NEAR(rows(0, j), image_distance(p.places[q], p.places[j]), 1e-9) << q << " " << j;
      } else {
        EXPECT_EQ(rows(0, j), std::numeric_limits<double>::infinity()) << q << " " << j;
      }
    }
  }
}

TEST(BirdsEyeMethod, DatabaseQueriesEqualTheirBruteForceOracles) {
  const Places p = street_places(36, 4);
  DatabaseConfig config;
  config.method = Method::BirdsEye;
  Database db(config), reloaded(config);
  for (int i = 0; i < 30; ++i) db.add({0, i}, {p.signatures[i]});
  std::vector<float> payload(db.payload_floats());
  for (int i = 0; i < 30; ++i) {
    db.stored_payload(i, payload.data());
    reloaded.add_stored({0, i}, payload.data(), Eigen::Matrix3f::Identity(), std::nullopt);
  }
  const int angles = BirdsEyePlaceConfig{}.angles;
  // The best image distance among the key's `finalists` best places.
  auto best_of_key_finalists = [&](const BirdsEyePlace& query, int finalists) {
    std::vector<std::pair<double, int>> by_key;
    for (int j = 0; j < 30; ++j) by_key.emplace_back(match_keys(query, p.places[j], angles).distance, j);
    std::sort(by_key.begin(), by_key.end());
    int best = by_key[0].second;
    for (int f = 1; f < finalists; ++f) {
      const int j = by_key[f].second;
      if (image_distance(query, p.places[j]) < image_distance(query, p.places[best])) best = j;
    }
    return best;
  };
  const auto matcher = make_birds_eye_matcher({}, {});  // the difference-matrix rows
  for (int i = 0; i < 30; ++i) matcher->add(p.signatures[i]);
  for (int q = 30; q < 36; ++q) {
    const BirdsEyePlace& query = p.places[q];
    // Exact: the image search of the key's finalists over every place, as the rows define it.
    const int best = best_of_key_finalists(query, BirdsEyeSearchConfig{}.finalists);
    Eigen::MatrixXd row;
    matcher->rows(p.signatures[q], 1000, 0, row);
    Eigen::Index row_best = 0;
    row.row(0).minCoeff(&row_best);
    EXPECT_EQ(row_best, best);
    QueryOptions exact;
    exact.retrieval = Retrieval::Exact;
    const auto e = db.query({p.signatures[q]}, 1, exact);
    ASSERT_EQ(e.size(), 1u);
    EXPECT_EQ(e[0].index, std::size_t(best));
    EXPECT_NEAR(e[0].distance, image_distance(query, p.places[best]), 1e-9);
    // Indexed: the best image distance among the key's best `candidates`.
    QueryOptions indexed;
    indexed.candidates = 4;
    const int best_finalist = best_of_key_finalists(query, 4);
    for (const Database* d : {&db, &reloaded}) {
      const auto r = d->query({p.signatures[q]}, 1, indexed);
      ASSERT_EQ(r.size(), 1u);
      EXPECT_EQ(r[0].index, std::size_t(best_finalist));
      const BirdsEyePlace& place = p.places[best_finalist];
      const BirdsEyePose pose =
          birds_eye_pose(query, place, match_keys(query, place, angles).yaw_rad, {}, {});
      EXPECT_NEAR(r[0].x_m, pose.x_m, 1e-9);
      EXPECT_NEAR(r[0].z_m, pose.z_m, 1e-9);
      EXPECT_NEAR(r[0].yaw_rad, pose.yaw_rad, 1e-9);
    }
  }
}

}  // namespace
}  // namespace loopscan
