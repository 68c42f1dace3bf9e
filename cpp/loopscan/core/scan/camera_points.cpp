#include "loopscan/core/scan/camera_points.hpp"

#include <cmath>
#include <cstdint>

#include "loopscan/core/scan/cell_select.hpp"
#include "loopscan/core/simd.hpp"

namespace loopscan {
namespace {

// atan2(y, x) in [-pi, pi] for float lanes: octant folding, a tan(15 deg) range reduction and
// a series to u^9 (error < 1e-7 rad, rounding included ~3e-7 rad). Selects only.
template <typename V>
LOOPSCAN_INLINE V approx_atan2(V y, V x) {
  const V ax = x < 0 ? -x : x, ay = y < 0 ? -y : y;
  const auto steep = ay > ax;
  const V mx = steep ? ay : ax, mn = steep ? ax : ay;
  const V t = mn / (mx > 0 ? mx : V{} + 1.f);
  const auto reduce = t > 0.26794919f;
  const V u = reduce ? (1.7320508f * t - 1.f) / (1.7320508f + t) : t;
  const V u2 = u * u;
  V s = V{} + 1.f / 9.f;
  s = s * u2 - 1.f / 7.f;
  s = s * u2 + 1.f / 5.f;
  s = s * u2 - 1.f / 3.f;
  V a = (reduce ? V{} + 0.52359878f : V{}) + (u + u * u2 * s);
  a = steep ? 1.5707963f - a : a;
  a = x < 0 ? 3.1415927f - a : a;
  return y < 0 ? -a : a;  // y = -0 goes to +a: within the margin of the +/-pi boundary anyway
}

struct KeyArgs {
  const CameraPoints* points;
  ScanFilter filter;
  float range, step_xz, step_y;  // Cartesian
  int nx, ny;
  float inv;  // polar: bins per radian
  int azimuth_bins;
  int outside_key;  // max_key + 1: no cell
  std::uint32_t* keys;
  float* scores;        // every score is a float value (the float coordinates' arithmetic)
  std::uint8_t* check;  // polar: 1 where a value is too close to a boundary for the float path
  std::size_t n_vec;    // the kernels cover [0, n_vec), a multiple of 8
};

template <int W>
LOOPSCAN_INLINE void compute_keys(const KeyArgs& a) {
  using V = typename simd::Vec<float, W>::type;
  using VI = typename simd::Vec<int, W>::type;
  constexpr int kV = simd::Vec<float, W>::kLanes;
  const CameraPoints& p = *a.points;
  for (std::size_t i = 0; i < a.n_vec; i += kV) {
    const V x = simd::load<V>(&p.x[i]), y = simd::load<V>(&p.y[i]), z = simd::load<V>(&p.z[i]);
    VI key;
    V score;
    if (a.filter == ScanFilter::Cartesian) {
      // Points outside the cube (and NaN) get the key no cell has: the selection drops them.
      // Their lanes are zeroed before the conversion, which only in-range values may reach.
      const VI inside = (x > -a.range) & (x < a.range) & (y > -a.range) & (y < a.range) &
                        (z > -a.range) & (z < a.range);
      const V zero{};
      // In range the shifted coordinates are positive: truncation is floor.
      const VI xi = __builtin_convertvector(inside ? (x + a.range) * a.step_xz : zero, VI);
      const VI yi = __builtin_convertvector(inside ? (y + a.range) * a.step_y : zero, VI);
      const VI zi = __builtin_convertvector(inside ? (z + a.range) * a.step_xz : zero, VI);
      key = inside ? xi + yi * a.nx + zi * (a.nx * a.ny) : VI{} + a.outside_key;
      score = y;
    } else {
      const V xz2 = x * x + z * z;
      V xz;
      for (int l = 0; l < kV; ++l) xz[l] = __builtin_sqrtf(xz2[l]);
      score = xz2 + y * y;
      // NaN / inf lanes go to the exact path, which drops them; zeroed here before conversion.
      const VI finite = score < __builtin_inff();
      const V zero{};
      const V va = finite ? (approx_atan2(z, x) + 3.1415927f) * a.inv : zero;
      const V ve = finite ? (approx_atan2(y, xz) + 1.5707963f) * a.inv : zero;
      const VI ia = __builtin_convertvector(va, VI), ie = __builtin_convertvector(ve, VI);
      const V fa = va - __builtin_convertvector(ia, V), fe = ve - __builtin_convertvector(ie, V);
      constexpr float kMargin = 1e-4f;  // in bins, far above the ~2e-5 bin error of the float path
      const VI near = (fa < kMargin) | (fa > 1.f - kMargin) | (fe < kMargin) | (fe > 1.f - kMargin);
      key = ia + ie * a.azimuth_bins;
      for (int l = 0; l < kV; ++l) a.check[i + l] = near[l] != 0 || finite[l] == 0;
    }
    for (int l = 0; l < kV; ++l) {
      a.keys[i + l] = static_cast<std::uint32_t>(key[l]);
      a.scores[i + l] = score[l];
    }
  }
}

void keys_base(const KeyArgs& a) { compute_keys<16>(a); }
LOOPSCAN_AVX2 void keys_avx2(const KeyArgs& a) { compute_keys<32>(a); }

}  // namespace

CameraPoints to_camera_points(const Cloud& cloud) {
  CameraPoints out;
  out.resize(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    out.x[i] = static_cast<float>(cloud[i].p.x());
    out.y[i] = static_cast<float>(cloud[i].p.y());
    out.z[i] = static_cast<float>(cloud[i].p.z());
    out.gray[i] = cloud[i].intensity;
  }
  return out;
}

Cloud to_cloud(const CameraPoints& p) {
  Cloud out(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    out[i] = {Eigen::Vector3d(p.x[i], p.y[i], p.z[i]), p.gray[i]};
  }
  return out;
}

Cloud filter_camera_points(const CameraPoints& p, ScanFilter filter, const ImitationConfig& c) {
  validate(c);
  const std::size_t n = p.size();
  thread_local std::vector<std::uint32_t> keys;
  thread_local std::vector<float> scores;
  thread_local std::vector<std::uint8_t> check;
  thread_local std::vector<int> kept;
  keys.resize(n);
  scores.resize(n);
  check.assign(n, 0);

  KeyArgs a{};
  a.points = &p;
  a.filter = filter;
  a.range = static_cast<float>(c.range_m);
  a.step_xz = static_cast<float>(1.0 / (c.range_m / c.voxel_divisions_xz));
  a.step_y = static_cast<float>(1.0 / (c.range_m / c.voxel_divisions_y));
  a.nx =
      static_cast<int>(std::floor(2 * c.range_m * (1.0 / (c.range_m / c.voxel_divisions_xz))) + 1);
  a.ny =
      static_cast<int>(std::floor(2 * c.range_m * (1.0 / (c.range_m / c.voxel_divisions_y))) + 1);
  const double inv = 1.0 / (c.polar_resolution_deg / 180.0 * M_PI);
  a.inv = static_cast<float>(inv);
  a.azimuth_bins = static_cast<int>(std::floor(2 * M_PI * inv) + 1);
  const std::uint32_t max_key =
      filter == ScanFilter::Cartesian
          ? static_cast<std::uint32_t>(a.nx * a.ny * a.nx - 1)
          : static_cast<std::uint32_t>(a.azimuth_bins * (std::floor(M_PI * inv) + 1) - 1);
  a.outside_key = static_cast<int>(max_key) + 1;
  a.keys = keys.data();
  a.scores = scores.data();
  a.check = check.data();
  a.n_vec = n - n % 8;
  (simd::has_avx2() ? keys_avx2 : keys_base)(a);

  // The tail that does not fill a vector, and the values next to a polar boundary.
  for (std::size_t i = 0; i < n; ++i) {
    if (i < a.n_vec && !check[i]) continue;
    const double x = p.x[i], y = p.y[i], z = p.z[i];
    if (filter == ScanFilter::Cartesian) {
      if (!(std::abs(p.x[i]) < a.range && std::abs(p.y[i]) < a.range &&
            std::abs(p.z[i]) < a.range)) {
        keys[i] = static_cast<std::uint32_t>(a.outside_key);
        continue;
      }
      const int xi = static_cast<int>((p.x[i] + a.range) * a.step_xz);
      const int yi = static_cast<int>((p.y[i] + a.range) * a.step_y);
      const int zi = static_cast<int>((p.z[i] + a.range) * a.step_xz);
      keys[i] = static_cast<std::uint32_t>(xi + yi * a.nx + zi * a.nx * a.ny);
      scores[i] = p.y[i];
    } else {
      if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
        keys[i] = static_cast<std::uint32_t>(a.outside_key);
        continue;
      }
      // Exact angles of the same float inputs the vector path saw.
      const float xz2f = p.x[i] * p.x[i] + p.z[i] * p.z[i];
      const double xzf = static_cast<double>(std::sqrt(xz2f));
      const int ia = static_cast<int>(std::floor((std::atan2(z, x) + M_PI) * inv));
      const int ie = static_cast<int>(std::floor((std::atan2(y, xzf) + M_PI / 2) * inv));
      keys[i] = static_cast<std::uint32_t>(ia + ie * a.azimuth_bins);
      scores[i] = xz2f + p.y[i] * p.y[i];
    }
  }
  best_per_cell(keys, scores, max_key, kept);
  Cloud out(kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const int i = kept[k];
    out[k] = {Eigen::Vector3d(p.x[i], p.y[i], p.z[i]), p.gray[i]};
  }
  return out;
}

}  // namespace loopscan
