#include "loopscan/sim/texture.hpp"

#include <algorithm>

#include "loopscan/core/simd.hpp"
#include "loopscan/sim/texture_noise.hpp"

namespace loopscan::sim {
namespace {

constexpr double kEdge = 0.04;  // edge width of windows and car parts

double clamp01(double a) { return std::clamp(a, 0.0, 1.0); }
double mix(double a, double b, double t) { return a + (b - a) * t; }

// Inlined into facade_albedo's ISA clones.
LOOPSCAN_INLINE double wall_albedo(const FacadeStyle& s, double u, double v) {
  if (s.brick) {
    // Large bricks/blocks (15 x 45 cm) with lighter mortar joints, running bond.
    const double course = 0.15, len = 0.45;
    const double row = std::floor(v / course);
    const double bu = u + (static_cast<std::int64_t>(row) % 2 != 0 ? 0.5 * len : 0.0);
    const double col = std::floor(bu / len);
    const double lu = bu - col * len, lv = v - row * course;
    const double brick =
        smooth_box(lu, 0.015, len - 0.015, 0.01) * smooth_box(lv, 0.015, course - 0.015, 0.01);
    const double tone = 0.1 * (hash_unit(s.salt, lattice(col), lattice(row), 3) - 0.5);
    return mix(s.wall + 0.12, s.wall + tone, brick);
  }
  return s.wall + 0.12 * (fbm2(0.5 * u, 0.5 * v, s.salt, 3) - 0.5) +
         0.04 * (value_noise2(6.0 * u, 6.0 * v, s.salt + 1) - 0.5);
}

}  // namespace

LOOPSCAN_SIM_CLONES double facade_albedo(const FacadeStyle& s, double u, double v,
                                         double face_width, double height) {
  double a = wall_albedo(s, u, v);
  // A darker cornice band between the ground floor and the upper floors.
  a = mix(a, 0.7 * a,
          smooth_box(v, s.ground_floor_height - 0.12, s.ground_floor_height + 0.12, kEdge));
  const double pitch = s.window_pitch;
  const int columns = static_cast<int>(std::floor((face_width - 1.0) / pitch));
  if (columns < 1) return clamp01(a);
  const double cu = u - 0.5 * (face_width - columns * pitch);
  const double k = std::floor(cu / pitch);
  if (k < 0 || k >= columns) return clamp01(a);
  double lu, lv, ww, wh, row;
  if (v >= s.ground_floor_height) {
    row = std::floor((v - s.ground_floor_height) / s.floor_height);
    const double floor_v = s.ground_floor_height + row * s.floor_height;
    if (floor_v + s.sill + s.window_height > height - 0.4) return clamp01(a);  // no room left
    lu = cu - k * pitch - 0.5 * (pitch - s.window_width);
    lv = v - floor_v - s.sill;
    ww = s.window_width;
    wh = s.window_height;
  } else if (s.shop_front) {
    row = -1;
    lu = cu - k * pitch - 0.15;
    lv = v - 0.5;
    ww = pitch - 0.3;
    wh = s.ground_floor_height - 0.9;
  } else {
    row = -1;
    lu = cu - k * pitch - 0.5 * (pitch - s.window_width);
    lv = v - 1.0;
    ww = s.window_width;
    wh = std::min(s.window_height, s.ground_floor_height - 1.4);
  }
  const double frame =
      smooth_box(lu, -0.08, ww + 0.08, kEdge) * smooth_box(lv, -0.08, wh + 0.08, kEdge);
  const double glass = smooth_box(lu, 0.0, ww, kEdge) * smooth_box(lv, 0.0, wh, kEdge);
  a = a * (1.0 - frame) + s.frame * (frame - glass);
  // Off the glass the pane would add +-0 to a sum that is never -0 (smooth boxes are >= +0,
  // s.frame > 0): the same value without it.
  if (glass == 0.0) return clamp01(a);
  // Each pane reflects something different; a soft gradient inside the pane.
  const double pane = s.glass + 0.16 * (hash_unit(s.salt, lattice(k), lattice(row), 11) - 0.5) +
                      0.05 * (value_noise2(1.5 * u, 1.5 * v, s.salt + 2) - 0.5);
  return clamp01(a + pane * glass);
}

namespace {

// base + coarse fBm + fine value noise: the shared shape of the horizontal-surface textures.
double layered_albedo(std::uint32_t salt, double x, double z, double base, double coarse_amp,
                      double coarse_freq, int octaves, double fine_amp, double fine_freq) {
  return clamp01(base + coarse_amp * (fbm2(coarse_freq * x, coarse_freq * z, salt, octaves) - 0.5) +
                 fine_amp * (value_noise2(fine_freq * x, fine_freq * z, salt + 1) - 0.5));
}

}  // namespace

LOOPSCAN_SIM_CLONES double roof_albedo(std::uint32_t salt, double x, double z) {
  return layered_albedo(salt, x, z, 0.3, 0.14, 0.4, 2, 0.06, 4.0);
}

LOOPSCAN_SIM_CLONES double road_albedo(std::uint32_t salt, double x, double z, double grain) {
  return layered_albedo(salt, x, z, 0.16, 0.05, 0.3, 2, grain, 6.0);  // dark
}

double lane_marking(double offset, double arc, double road_half_width, double lane_width) {
  constexpr double kLine = 0.15, kEdgeLine = 0.2, kSoft = 0.02;
  constexpr double kDash = 6.0, kDashPeriod = 18.0;  // 6 m painted, 12 m gap
  const double edge = road_half_width - 0.35;
  double paint = road_half_width > 1.0
                     ? smooth_box(offset, edge - 0.5 * kEdgeLine, edge + 0.5 * kEdgeLine, kSoft)
                     : 0.0;
  // The lane lines: half a lane either side of the centreline, then every lane, while a lane's
  // width is left before the edge line.
  const double k = std::round((offset - 0.5 * lane_width) / lane_width);
  const double line = 0.5 * lane_width + std::max(k, 0.0) * lane_width;
  if (line < edge - 0.5 * lane_width) {
    const double along = arc - kDashPeriod * std::floor(arc / kDashPeriod);
    paint = std::max(paint, smooth_box(offset, line - 0.5 * kLine, line + 0.5 * kLine, kSoft) *
                                smooth_box(along, 0.0, kDash, kSoft));
  }
  return paint;
}

double guard_rail_albedo(std::uint32_t salt, double u, double v) {
  constexpr double kPostPitch = 2.0, kPostWidth = 0.12;
  if (v >= kGuardRailBeamBottom) {  // the galvanised beam with its two grooves
    const double groove =
        std::max(smooth_box(v, 0.52, 0.55, 0.01), smooth_box(v, 0.65, 0.68, 0.01));
    return clamp01(0.58 - 0.18 * groove + 0.06 * (value_noise2(1.5 * u, 8.0 * v, salt) - 0.5));
  }
  // Below the beam: its shadow, crossed by the posts.
  const double lu = u - kPostPitch * std::floor(u / kPostPitch);
  const double post = smooth_box(lu, 0.0, kPostWidth, 0.01);
  return clamp01(mix(0.08, 0.45, post) + 0.03 * (value_noise2(4.0 * u, 4.0 * v, salt + 1) - 0.5));
}

LOOPSCAN_SIM_CLONES double sidewalk_albedo(std::uint32_t salt, double x, double z) {
  const double tile = 0.5;
  const double tx = std::floor(x / tile), tz = std::floor(z / tile);
  const double lx = x - tx * tile, lz = z - tz * tile;
  const double inside =
      smooth_box(lx, 0.015, tile - 0.015, 0.01) * smooth_box(lz, 0.015, tile - 0.015, 0.01);
  const double tone = 0.06 * (hash_unit(salt, lattice(tx), lattice(tz)) - 0.5);
  return clamp01(0.36 + 0.12 * inside + tone +
                 0.02 * (value_noise2(5.0 * x, 5.0 * z, salt + 1) - 0.5));
}

LOOPSCAN_SIM_CLONES double grass_albedo(std::uint32_t salt, double x, double z) {
  return layered_albedo(salt, x, z, 0.26, 0.16, 0.4, 3, 0.08, 5.0);
}

LOOPSCAN_SIM_CLONES double snow_albedo(std::uint32_t salt, double x, double z) {
  return layered_albedo(salt, x, z, 0.9, 0.03, 0.2, 2, 0.01, 3.0);  // snow hides the texture
}

LOOPSCAN_SIM_CLONES double bark_albedo(std::uint32_t salt, double base, double u, double v) {
  // Vertical stripes: fast variation around the trunk, slow along it.
  return clamp01(base + 0.12 * (value_noise2(10.0 * u, 0.8 * v, salt) - 0.5) +
                 0.05 * (value_noise2(25.0 * u, 3.0 * v, salt + 1) - 0.5));
}

LOOPSCAN_SIM_CLONES double leaf_albedo(std::uint32_t salt, double base, double x, double y,
                                       double z) {
  return clamp01(base + 0.2 * (value_noise3(10.0 * x, 10.0 * y, 10.0 * z, salt) - 0.5) +
                 0.1 * (value_noise3(3.0 * x, 3.0 * y, 3.0 * z, salt + 1) - 0.5));
}

LOOPSCAN_SIM_CLONES double car_side_albedo(const CarStyle& s, double u, double v) {
  if (!s.front_at_plus_u) u = s.length - u;
  double a = s.body + 0.03 * (value_noise2(2.0 * u, 2.0 * v, s.salt) - 0.5);
  a = mix(a, 0.5 * s.body + 0.05, smooth_box(v, -1.0, 0.35, kEdge));  // sill / bumper line
  for (const double wc : {0.8, s.length - 0.9}) {
    const double d = std::sqrt((u - wc) * (u - wc) + (v - 0.33) * (v - 0.33));
    a = mix(a, 0.06, 1.0 - smoothstep(0.30, 0.34, d));  // tyre
    a = mix(a, 0.55, 1.0 - smoothstep(0.13, 0.17, d));  // rim
  }
  const double mid = 0.5 * s.length;
  const double window = smooth_box(v, 0.95, s.height - 0.08, kEdge) *
                        smooth_box(u, 0.6, s.length - 0.9, kEdge) *
                        (1.0 - smooth_box(u, mid - 0.06, mid + 0.06, kEdge));
  return clamp01(mix(a, s.glass, window));
}

LOOPSCAN_SIM_CLONES double car_end_albedo(const CarStyle& s, double u, double v, bool front) {
  const double w = s.width;
  double a = s.body;
  a = mix(a, 0.08, smooth_box(v, -1.0, 0.4, kEdge));  // bumper
  a = mix(a, s.glass,
          smooth_box(v, 0.95, s.height - 0.1, kEdge) * smooth_box(u, 0.15, w - 0.15, kEdge));
  const double lights = smooth_box(v, 0.6, 0.75, kEdge) *
                        (smooth_box(u, 0.1, 0.35, kEdge) + smooth_box(u, w - 0.35, w - 0.1, kEdge));
  a = mix(a, front ? 0.9 : 0.3, lights);
  a = mix(a, 0.85,
          smooth_box(u, 0.5 * w - 0.26, 0.5 * w + 0.26, kEdge) *
              smooth_box(v, 0.3, 0.42, kEdge));  // number plate
  return clamp01(a);
}

LOOPSCAN_SIM_CLONES double car_roof_albedo(const CarStyle& s, double u, double v) {
  return clamp01(s.body * 1.05 + 0.03 * (value_noise2(2.0 * u, 2.0 * v, s.salt + 5) - 0.5));
}

}  // namespace loopscan::sim
