#pragma once
// Albedo textures (0..1) of the world's surfaces as functions of surface coordinates in metres,
// plus finite-difference gradients for DSO-like point selection.
#include <cmath>
#include <cstdint>

namespace loopscan::sim {

struct TextureSample {
  double albedo = 0.0;
  double gradient = 0.0;  // |d albedo / d metre| on the surface
};

// Central differences with a 1 cm step: edges are smoothed over a few cm, so this resolves them.
// Without `gradient` only the albedo is evaluated (the renderer needs no gradient: 5x cheaper).
template <class F>
TextureSample sample_surface(const F& f, double u, double v, bool gradient = true,
                             double h = 0.01) {
  if (!gradient) return {f(u, v), 0.0};
  const double du = (f(u + h, v) - f(u - h, v)) / (2.0 * h);
  const double dv = (f(u, v + h) - f(u, v - h)) / (2.0 * h);
  return {f(u, v), std::sqrt(du * du + dv * dv)};
}

template <class F>
TextureSample sample_volume(const F& f, double x, double y, double z, bool gradient = true,
                            double h = 0.01) {
  if (!gradient) return {f(x, y, z), 0.0};
  const double dx = (f(x + h, y, z) - f(x - h, y, z)) / (2.0 * h);
  const double dy = (f(x, y + h, z) - f(x, y - h, z)) / (2.0 * h);
  const double dz = (f(x, y, z + h) - f(x, y, z - h)) / (2.0 * h);
  return {f(x, y, z), std::sqrt(dx * dx + dy * dy + dz * dz)};
}

struct FacadeStyle {
  double wall = 0.5;    // base wall albedo
  double glass = 0.15;  // window glass
  double frame = 0.75;  // window frames
  double floor_height = 3.0;
  double ground_floor_height = 3.6;
  double window_pitch = 2.6;  // horizontal spacing of window columns
  double window_width = 1.2;
  double window_height = 1.5;
  double sill = 0.9;  // window bottom above the floor
  bool brick = false;
  bool shop_front = false;  // wide shop windows on the ground floor
  std::uint32_t salt = 0;
};

struct CarStyle {
  double body = 0.5;
  double glass = 0.1;
  double length = 4.4;
  double width = 1.8;
  double height = 1.5;
  bool front_at_plus_u = true;  // headlights at the +u end
  std::uint32_t salt = 0;
};

// Facade face: u along the face from one corner (face_width wide), v height above the ground.
double facade_albedo(const FacadeStyle& s, double u, double v, double face_width, double height);
// Horizontal surfaces, in world (x, z).
double roof_albedo(std::uint32_t salt, double x, double z);
double road_albedo(std::uint32_t salt, double x, double z, double grain);
// Paint (0..1) of the road markings at `offset` metres from the centreline, `arc` metres along
// it: a dashed line between lanes (the first half a lane off the centreline) and a solid edge
// line.
double lane_marking(double offset, double arc, double road_half_width, double lane_width);
// Guard rail face: u along the rail, v height above the ground (the beam from
// kGuardRailBeamBottom to kGuardRailHeight, posts every 2 m below it).
inline constexpr double kGuardRailHeight = 0.75, kGuardRailBeamBottom = 0.45;
double guard_rail_albedo(std::uint32_t salt, double u, double v);
double sidewalk_albedo(std::uint32_t salt, double x, double z);
double grass_albedo(std::uint32_t salt, double x, double z);
double snow_albedo(std::uint32_t salt, double x, double z);
// Trunk: u arc length around the trunk, v height above the ground.
double bark_albedo(std::uint32_t salt, double base, double u, double v);
// Foliage: volumetric leafy noise around `base`, in world coordinates.
double leaf_albedo(std::uint32_t salt, double base, double x, double y, double z);
// Car: side (u along the length, v above the ground), end (u across the width), roof.
double car_side_albedo(const CarStyle& s, double u, double v);
double car_end_albedo(const CarStyle& s, double u, double v, bool front);
double car_roof_albedo(const CarStyle& s, double u, double v);

}  // namespace loopscan::sim
