// Ray casting: the ground (a local plane under the nearest centreline point) bounds the walk
// through the object grid; only the nearest hit is shaded.
#include <algorithm>
#include <cmath>

#include "loopscan/sim/texture_noise.hpp"
#include "loopscan/sim/world_internal.hpp"

namespace loopscan::sim {
namespace {

constexpr std::size_t kMaxSessions = 8;

}  // namespace

World::CarCache::Cars World::CarCache::get(const StaticWorld& world, unsigned session_seed) {
  std::lock_guard<std::mutex> lock(mutex);
  for (const auto& [seed, cars] : sessions)
    if (seed == session_seed) return cars;
  if (sessions.size() >= kMaxSessions) sessions.erase(sessions.begin());
  sessions.emplace_back(session_seed, std::make_shared<const std::vector<ParkedCar>>(
                                          draw_parked_cars(world, session_seed)));
  return sessions.back().second;
}

LOOPSCAN_SIM_CLONES bool foliage_hit(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double t0,
                                     double t1, double voxel, double density, std::uint32_t salt,
                                     double& t_hit) {
  t0 = std::max(t0, 0.0);
  if (density <= 0.0 || t1 <= t0) return false;
  const Eigen::Vector3d p = o + t0 * d;
  std::int64_t idx[3];
  int step[3];
  double t_next[3], t_delta[3];
  for (int a = 0; a < 3; ++a) {
    const double cell = std::floor(p[a] / voxel);
    idx[a] = static_cast<std::int64_t>(cell);
    if (std::abs(d[a]) < 1e-300) {
      step[a] = 0;
      t_next[a] = t_delta[a] = 1e300;
    } else {
      step[a] = d[a] > 0 ? 1 : -1;
      t_next[a] = t0 + ((cell + (d[a] > 0 ? 1.0 : 0.0)) * voxel - p[a]) / d[a];
      t_delta[a] = voxel / std::abs(d[a]);
    }
  }
  double t = t0;
  for (int guard = 0; guard < 100000; ++guard) {
    if (hash_unit(salt, static_cast<std::uint32_t>(idx[0]), static_cast<std::uint32_t>(idx[1]),
                  static_cast<std::uint32_t>(idx[2])) < density) {
      t_hit = t;
      return true;
    }
    const int a =
        t_next[0] < t_next[1] ? (t_next[0] < t_next[2] ? 0 : 2) : (t_next[1] < t_next[2] ? 1 : 2);
    t = t_next[a];
    if (t >= t1) return false;
    idx[a] += step[a];
    t_next[a] += t_delta[a];
  }
  return false;
}

std::optional<Hit> World::raycast(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                  double max_distance, const Conditions& conditions) const {
  if (!world_ || !(max_distance > 0.0) || !origin.allFinite() || !direction.allFinite())
    return std::nullopt;
  const StaticWorld& w = *world_;
  double t_best = max_distance;
  HitRef best;
  const double tg = ground_t(w, origin, direction);
  if (tg >= 0.0 && tg < t_best) {
    t_best = tg;
    best.ground = best.found = true;
  }
  const double density = foliage_density(conditions.season);
  CarCache::Cars cars;  // fetched on the first car slot the ray meets
  const auto get_cars = [&]() -> const std::vector<ParkedCar>& {
    if (!cars) cars = cars_->get(w, conditions.session_seed);
    return *cars;
  };
  w.grid.traverse(origin, direction, t_best, [&](std::uint32_t code) {
    test_object(w, code, origin, direction, density, get_cars, t_best, best);
  });
  if (!best.found) return std::nullopt;
  return shade_hit(w, best, origin, direction, t_best, cars.get(), conditions, true);
}

}  // namespace loopscan::sim
