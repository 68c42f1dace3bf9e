#pragma once
// Rectified grayscale stereo images of the synthetic world: one ray per pixel, tested against
// the objects whose projection covers its tile (nearest first; see render_visibility.hpp), shaded
// like the VO simulator's points (255 (gain * albedo)^gamma), sky where nothing is hit, plus a
// little seeded sensor noise. The right camera sits one baseline along the left camera's x axis, as
// in KITTI.
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "loopscan/sim/camera.hpp"
#include "loopscan/sim/world.hpp"

namespace loopscan::sim {

struct GrayImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;  // row-major
  std::uint8_t at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

struct RenderConfig {
  double max_distance_m = 150.0;
  double sky_gray = 200.0;   // at the horizon; darker towards the zenith
  double noise_sigma = 1.0;  // sensor noise, gray levels
  unsigned seed = 1;         // noise seed (mixed with the frame and the camera)
  int threads = 1;
  // The oracle: World::raycast for every pixel (grid walk, full shading) instead of the tile
  // lists of the objects in view. Same images, ~10x slower; for tests.
  bool raycast_every_pixel = false;
  // The oracle of the ground caches: CentrelineIndex::nearest for every ground query of the
  // tile renderer (sloped streets). Same images; for tests.
  bool exact_ground = false;
};

// The camera scaled by `scale` (image size and intrinsics; the baseline stays).
StereoCamera scaled_camera(const StereoCamera& camera, double scale);

// camera_index 0 = left (at T_world_cam), 1 = right (baseline along the left camera's x).
GrayImage render_view(const World& world, const Conditions& conditions, const StereoCamera& camera,
                      const Eigen::Isometry3d& T_world_cam, int camera_index, int frame,
                      const RenderConfig& config);

// Distance along every pixel's ray (unit length) to the surface it shows, 0 for sky; row-major.
// The geometry render_view shades, for tests and tools.
std::vector<double> render_depth(const World& world, const Conditions& conditions,
                                 const StereoCamera& camera, const Eigen::Isometry3d& T_world_cam,
                                 int camera_index, const RenderConfig& config);

}  // namespace loopscan::sim
