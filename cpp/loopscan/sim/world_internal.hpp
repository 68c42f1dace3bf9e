#pragma once
// Internals of World shared by world.cpp, world_raycast.cpp and world_shading.cpp.
#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "loopscan/core/simd.hpp"
#include "loopscan/sim/world.hpp"
#include "loopscan/sim/world_objects.hpp"

namespace loopscan::sim {

// Parked cars per session, drawn on first use. A few sessions are kept: the simulator renders
// one session at a time, so the lock is uncontended and taken once per ray that meets a slot.
struct World::CarCache {
  using Cars = std::shared_ptr<const std::vector<ParkedCar>>;
  std::mutex mutex;
  std::vector<std::pair<unsigned, Cars>> sessions;
  Cars get(const StaticWorld& world, unsigned session_seed);
};

// First occupied foliage voxel along the chord [t0, t1] of a crown (3D DDA over a world-aligned
// voxel grid, occupancy hashed per voxel: the same leaves seen from every viewpoint).
bool foliage_hit(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double t0, double t1,
                 double voxel, double density, std::uint32_t salt, double& t_hit);

// Renderer access to the world's internals (World befriends it).
struct WorldAccess {
  static const StaticWorld* world(const World& w) { return w.world_.get(); }
  static std::shared_ptr<const std::vector<ParkedCar>> cars(const World& w, unsigned session_seed) {
    return w.cars_->get(*w.world_, session_seed);
  }
};

// Ray parameter of the ground hit, or a negative value if the ray does not reach the ground;
// ground_y(x, z) gives ground_y_at(w, x, z) (the renderer answers it from a local cache).
template <class GroundY>
LOOPSCAN_INLINE double ground_t_with(const StaticWorld& w, const Eigen::Vector3d& o,
                                     const Eigen::Vector3d& d, GroundY&& ground_y) {
  if (w.centreline.empty() || d.y() <= 1e-12) return -1.0;
  double g = ground_y(o.x(), o.z());
  if (o.y() >= g) return -1.0;  // at or below the ground
  double t = (g - o.y()) / d.y();
  if (w.flat) return t;
  // Sloped streets: iterate the local plane under the hit point (a few steps converge).
  for (int it = 0; it < 6; ++it) {
    const Eigen::Vector3d p = o + t * d;
    g = ground_y(p.x(), p.z());
    const double t2 = (g - o.y()) / d.y();
    if (t2 <= 0.0) return -1.0;
    const bool done = std::abs(t2 - t) < 1e-9 * std::max(1.0, t);
    t = t2;
    if (done) break;
  }
  return t;
}

inline double ground_t(const StaticWorld& w, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  return ground_t_with(w, o, d, [&](double x, double z) { return ground_y_at(w, x, z); });
}

// What a ray met, before shading: the ground or the nearest object (by its grid code).
struct HitRef {
  std::uint32_t code = 0;
  int face = 0;
  bool cap = false;
  bool ground = false;
  bool found = false;
};

// Lowers t_best to the ray's first crossing with object `code` if nearer and records it in best.
// cars() gives this session's parked cars; it is called only when a car slot is met.
template <class Cars>
inline void test_object(const StaticWorld& w, std::uint32_t code, const Eigen::Vector3d& o,
                        const Eigen::Vector3d& d, double density, Cars&& cars, double& t_best,
                        HitRef& best) {
  const std::size_t i = code_index(code);
  double t = 0.0;
  int face = 0;
  bool cap = false;
  switch (code_kind(code)) {
    case ObjectKind::Facade:
      if (!intersect_box(w.facades[i].box, o, d, t_best, t, face)) return;
      break;
    case ObjectKind::Post:
      if (!intersect_cylinder(w.posts[i].cylinder, o, d, t_best, t, cap)) return;
      break;
    case ObjectKind::Crown: {
      double t0, t1;
      if (!intersect_ellipsoid(w.crowns[i].ellipsoid, o, d, t0, t1) || t0 >= t_best) return;
      if (!foliage_hit(o, d, t0, std::min(t1, t_best), w.config.foliage_voxel_m, density,
                       w.foliage_salt, t))
        return;
      break;
    }
    case ObjectKind::CarSlot: {
      const ParkedCar& car = cars()[i];
      if (!car.present || !intersect_box(car.box, o, d, t_best, t, face)) return;
      break;
    }
  }
  if (t >= t_best) return;
  t_best = t;
  best = HitRef{code, face, cap, false, true};
}

// Road, sidewalk or ground at a ground point, by its horizontal distance to the centreline.
Surface ground_surface(const StaticWorld& w, double centreline_distance);
// A ground hit of a known surface class (what shade_hit does for ground hits after the query).
Hit shade_ground_as(const StaticWorld& w, Surface s, const Eigen::Vector3d& p, double t,
                    const Conditions& c, bool gradient);

// Surface, albedo (season applied) and, if `gradient`, texture gradient of a found hit at
// distance t; cars: this session's parked cars (needed for car hits only).
Hit shade_hit(const StaticWorld& w, const HitRef& ref, const Eigen::Vector3d& o,
              const Eigen::Vector3d& d, double t, const std::vector<ParkedCar>* cars,
              const Conditions& c, bool gradient);

// The albedo alone of shade_hit(..., gradient = false) and shade_ground_as (the renderer's
// entry points: the same value, without building the rest of the Hit).
double shade_albedo(const StaticWorld& w, const HitRef& ref, const Eigen::Vector3d& o,
                    const Eigen::Vector3d& d, double t, const std::vector<ParkedCar>* cars,
                    const Conditions& c);
double ground_albedo_as(const StaticWorld& w, Surface s, const Eigen::Vector3d& p,
                        const Conditions& c);

}  // namespace loopscan::sim
