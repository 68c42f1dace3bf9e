#include "loopscan/sim/renderer.hpp"

#include <algorithm>
#include <cmath>

#include "loopscan/core/parallel.hpp"
#include "loopscan/core/simd.hpp"
#include "loopscan/sim/render_ground.hpp"
#include "loopscan/sim/render_noise.hpp"
#include "loopscan/sim/render_visibility.hpp"
#include "loopscan/sim/texture_noise.hpp"
#include "loopscan/sim/world_internal.hpp"

namespace loopscan::sim {
namespace {

// One view: camera centre, rotation, this session's cars and the tile lists of the objects.
struct View {
  const StaticWorld* world = nullptr;  // null: an empty world, every ray misses
  std::shared_ptr<const std::vector<ParkedCar>> cars;
  Eigen::Vector3d origin;
  Eigen::Matrix3d R;
  TileBins bins;
  double density = 0.0;
  std::vector<double> ray_x;  // (u - cx) / fx of every column: one division a column, not a pixel
};

View make_view(const World& world, const Conditions& conditions, const StereoCamera& camera,
               const Eigen::Isometry3d& T_world_cam, int camera_index, double max_distance) {
  View view;
  view.ray_x.resize(static_cast<std::size_t>(std::max(camera.width, 0)));
  for (int u = 0; u < camera.width; ++u) view.ray_x[u] = (u - camera.cx) / camera.fx;
  view.origin =
      T_world_cam * Eigen::Vector3d(camera_index == 1 ? camera.baseline() : 0.0, 0.0, 0.0);
  view.R = T_world_cam.linear();
  view.world = WorldAccess::world(world);
  if (!view.world || !(max_distance > 0.0) || !view.origin.allFinite() || !view.R.allFinite()) {
    view.world = nullptr;
    return view;
  }
  view.cars = WorldAccess::cars(world, conditions.session_seed);
  view.bins = bin_view(*view.world, *view.cars, camera, view.origin, view.R, max_distance);
  view.density = foliage_density(conditions.season);
  return view;
}

// Nearest hit of pixel (u, v)'s ray d within t_best (lowered to it): the ground, then the
// tile's objects nearest first, as World::raycast finds it.
// Inlined into render_row (and its ISA clones).
LOOPSCAN_INLINE HitRef first_hit(const View& view, int u, int v, const Eigen::Vector3d& d,
                                 double& t_best, GroundCaches& caches) {
  HitRef best;
  const StaticWorld& w = *view.world;
  int step = 0;
  const double tg = ground_t_with(w, view.origin, d,
                                  [&](double x, double z) { return caches.y_at(step++, x, z); });
  if (tg >= 0.0 && tg < t_best) {
    t_best = tg;
    best.ground = best.found = true;
  }
  const TileBins& b = view.bins;
  const std::size_t tile =
      static_cast<std::size_t>(v / TileBins::kTile) * b.tiles_x + u / TileBins::kTile;
  const auto cars = [&]() -> const std::vector<ParkedCar>& { return *view.cars; };
  for (std::uint32_t k = b.start[tile]; k < b.start[tile + 1]; ++k) {
    const ViewCandidate& c = b.items[k];
    if (c.min_distance >= t_best) break;  // this and every later object are farther
    if (u < c.u0 || u > c.u1 || v < c.v0 || v > c.v1) continue;
    test_object(w, c.code, view.origin, d, view.density, cars, t_best, best);
  }
  return best;
}

// The albedo of a hit found by first_hit (inlined into render_row's ISA clones).
LOOPSCAN_INLINE double shade(const View& view, const HitRef& ref, const Eigen::Vector3d& d,
                             double t, const Conditions& conditions, GroundCaches& ground) {
  if (!ref.ground)
    return shade_albedo(*view.world, ref, view.origin, d, t, view.cars.get(), conditions);
  const Eigen::Vector3d p = view.origin + t * d;
  return ground_albedo_as(*view.world, ground.surface_at(p.x(), p.z()), p, conditions);
}

// camera.ray(u, v) rotated into the world, its expression inlined (the call was 2.5 % of a
// render) with the column's x from the table: the same operations, the same bits. ray_y: the
// row's (v - cy) / fy.
LOOPSCAN_INLINE Eigen::Vector3d world_ray(const View& view, int u, double ray_y) {
  return view.R * Eigen::Vector3d(view.ray_x[static_cast<std::size_t>(u)], ray_y, 1.0).normalized();
}

// std::lround(g) clamped to 0..255 without the library call: g - trunc(g) is exact, so
// comparing it with 0.5 rounds halves away from zero exactly as lround does.
std::uint8_t gray_level(double g) {
  g = g >= -1.0 ? std::min(g, 256.0) : -1.0;  // NaN -> -1 -> 0
  const int i = static_cast<int>(g);
  const double f = g - i;
  return static_cast<std::uint8_t>(std::clamp(i + (f >= 0.5) - (f <= -0.5), 0, 255));
}

// Runs pixel(u, v, ray, hit) over the image rows split between the threads; rows(v) starts a
// row (per-row state such as the noise stream).
template <class Row>
void for_each_row(const StereoCamera& camera, int threads, Row&& row) {
  for_each_index(std::size_t(std::max(camera.height, 0)), threads,
                 [&](std::size_t v) { row(int(v)); });
}

struct RowJob {
  const World& world;
  const Conditions& conditions;
  const StereoCamera& camera;
  const View& view;
  const RenderConfig& config;
  int frame, camera_index;
  std::vector<std::uint8_t>& pixels;
};

// Row v of a view: ray, nearest hit, albedo, gray, sensor noise.
LOOPSCAN_SIM_CLONES void render_row(const RowJob& job, int v) {
  const auto& [world, conditions, camera, view, config, frame, camera_index, pixels] = job;
  // One noise stream per row: the image does not depend on the thread count.
  GaussianNoise noise(config.seed * 2654435761u + static_cast<unsigned>(frame) * 97u +
                          static_cast<unsigned>(camera_index) * 7919u + static_cast<unsigned>(v),
                      config.noise_sigma > 0 ? config.noise_sigma : 1.0);
  std::optional<GroundCaches> ground;
  if (view.world) ground.emplace(*view.world, view.origin, config.exact_ground);
  const double ray_y = (v - camera.cy) / camera.fy;
  for (int u = 0; u < camera.width; ++u) {
    const Eigen::Vector3d ray = world_ray(view, u, ray_y);
    Hit hit;  // only its albedo is used
    bool found = false;
    if (config.raycast_every_pixel) {
      const auto h = world.raycast(view.origin, ray, config.max_distance_m, conditions);
      if ((found = h.has_value())) hit.albedo = h->albedo;
    } else if (view.world) {
      double t = config.max_distance_m;
      const HitRef ref = first_hit(view, u, v, ray, t, *ground);
      if ((found = ref.found)) hit.albedo = shade(view, ref, ray, t, conditions, *ground);
    }
    // Sky: brighter towards the horizon (world y points down: -ray.y is the elevation).
    double g = found ? World::gray(hit, conditions)
                     : config.sky_gray * (1.0 - 0.25 * std::clamp(-ray.y(), 0.0, 1.0));
    if (config.noise_sigma > 0) g += noise();
    pixels[static_cast<std::size_t>(v) * camera.width + u] = gray_level(g);
  }
}

}  // namespace

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
  const View view =
      make_view(world, conditions, camera, T_world_cam, camera_index, config.max_distance_m);
  const RowJob job{world, conditions, camera, view, config, frame, camera_index, image.pixels};
  for_each_row(camera, config.threads, [&](int v) { render_row(job, v); });
  return image;
}

std::vector<double> render_depth(const World& world, const Conditions& conditions,
                                 const StereoCamera& camera, const Eigen::Isometry3d& T_world_cam,
                                 int camera_index, const RenderConfig& config) {
  std::vector<double> depth(static_cast<std::size_t>(camera.width) * camera.height, 0.0);
  const View view =
      make_view(world, conditions, camera, T_world_cam, camera_index, config.max_distance_m);
  for_each_row(camera, config.threads, [&](int v) {
    std::optional<GroundCaches> ground;
    if (view.world) ground.emplace(*view.world, view.origin, config.exact_ground);
    const double ray_y = (v - camera.cy) / camera.fy;
    for (int u = 0; u < camera.width; ++u) {
      const Eigen::Vector3d ray = world_ray(view, u, ray_y);
      double t = 0.0;
      if (config.raycast_every_pixel) {
        const auto hit = world.raycast(view.origin, ray, config.max_distance_m, conditions);
        if (hit) t = hit->distance;
      } else if (view.world) {
        double t_best = config.max_distance_m;
        if (first_hit(view, u, v, ray, t_best, *ground).found) t = t_best;
      }
      depth[static_cast<std::size_t>(v) * camera.width + u] = t;
    }
  });
  return depth;
}

}  // namespace loopscan::sim
