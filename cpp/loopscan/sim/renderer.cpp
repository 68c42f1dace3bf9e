#include "loopscan/sim/renderer.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "loopscan/core/parallel.hpp"

namespace loopscan::sim {

StereoCamera scaled_camera(const StereoCamera& camera, double scale) {
  StereoCamera c = camera;
  c.width = std::max(1, static_cast<int>(std::lround(camera.width * scale)));
  c.height = std::max(1, static_cast<int>(std::lround(camera.height * scale)));
  c.fx *= scale;
  c.fy *= scale;
  // Pixel centres at integer coordinates: the principal point scales about -0.5.
  c.cx = (camera.cx + 0.5) * scale - 0.5;
  c.cy = (camera.cy + 0.5) * scale - 0.5;
  c.bf = camera.bf * scale;
  return c;
}

GrayImage render_view(const World& world, const Conditions& conditions, const StereoCamera& camera,
                      const Eigen::Isometry3d& T_world_cam, int camera_index, int frame,
                      const RenderConfig& config) {
  GrayImage image;
  image.width = camera.width;
  image.height = camera.height;
  image.pixels.assign(static_cast<std::size_t>(camera.width) * camera.height, 0);
  const Eigen::Vector3d origin =
      T_world_cam * Eigen::Vector3d(camera_index == 1 ? camera.baseline() : 0.0, 0.0, 0.0);
  const Eigen::Matrix3d R = T_world_cam.linear();
  const int threads = std::max(1, config.threads);
  run_on_threads(threads, [&](int t) {
    for (int v = t; v < camera.height; v += threads) {
      // One noise stream per row: the image does not depend on the thread count.
      std::mt19937 rng(config.seed * 2654435761u + static_cast<unsigned>(frame) * 97u +
                       static_cast<unsigned>(camera_index) * 7919u + static_cast<unsigned>(v));
      std::normal_distribution<double> noise(0.0,
                                             config.noise_sigma > 0 ? config.noise_sigma : 1.0);
      for (int u = 0; u < camera.width; ++u) {
        const Eigen::Vector3d ray = R * camera.ray(u, v);
        const auto hit = world.raycast(origin, ray, config.max_distance_m, conditions);
        // Sky: brighter towards the horizon (world y points down: -ray.y is the elevation).
        double g = hit ? World::gray(*hit, conditions)
                       : config.sky_gray * (1.0 - 0.25 * std::clamp(-ray.y(), 0.0, 1.0));
        if (config.noise_sigma > 0) g += noise(rng);
        image.pixels[static_cast<std::size_t>(v) * camera.width + u] =
            static_cast<std::uint8_t>(std::clamp(std::lround(g), 0l, 255l));
      }
    }
  });
  return image;
}

}  // namespace loopscan::sim
