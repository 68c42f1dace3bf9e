#pragma once
// A deterministic synthetic street world for the stereo-VO simulator: built once from the
// centreline of a trajectory (so revisited places are the same place), rendered by ray casting
// under session conditions (season, light, parked cars).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

#include "loopscan/sim/conditions.hpp"
#include "loopscan/sim/world_config.hpp"
#include "loopscan/sim/world_primitives.hpp"

namespace loopscan::sim {

struct Hit {
  double distance = 0;                              // along the (unit) ray
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // world frame
  Surface surface = Surface::Ground;
  double albedo = 0;            // 0..1, after season effects, before illumination
  double texture_gradient = 0;  // |d albedo / d metre| on the surface at the hit
  int object_id = -1;           // stable id of the primitive (cars: stable within a session)
};

// Explicit geometry for tests and tools: boxes become facades (flat roof), cylinders poles,
// ellipsoids tree crowns. The ground still follows the centreline.
struct ExplicitPrimitives {
  std::vector<Box> facades;
  std::vector<Cylinder> poles;
  std::vector<Ellipsoid> crowns;
};

struct StaticWorld;

class World {
 public:
  World();  // empty: every ray misses

  // Builds the static world along the centreline (camera centres, world frame: x, z
  // horizontal, y down; the ground lies camera_height_m below the nearest centreline point).
  static World build(const std::vector<Eigen::Vector3d>& centreline, const WorldConfig& config);
  // The same ground, but exactly the given primitives (no generated objects, no cars).
  static World from_primitives(const std::vector<Eigen::Vector3d>& centreline,
                               const WorldConfig& config, const ExplicitPrimitives& primitives);

  // First surface hit by the ray (origin, unit direction) within max_distance under the
  // conditions (foliage, snow, this session's parked cars); nullopt if nothing is hit.
  // Thread-safe.
  std::optional<Hit> raycast(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                             double max_distance, const Conditions& conditions) const;

  // Gray value 0..255 of a hit under the conditions' illumination (inline: once per pixel).
  static double gray(const Hit& hit, const Conditions& conditions) {
    const double x = std::clamp(conditions.illumination_gain * hit.albedo, 0.0, 1.0);
    return 255.0 * (conditions.gamma == 1.0 ? x : std::pow(x, conditions.gamma));
  }

  // Static primitives (facades, trunks, crowns, poles); parked cars depend on the session.
  std::size_t object_count() const;
  // Every parameter used (seed, config, counts, a digest of the geometry), for world.json.
  nlohmann::json parameters() const;

 private:
  friend struct WorldAccess;  // the renderer's visibility pass
  struct CarCache;
  std::shared_ptr<const StaticWorld> world_;
  std::shared_ptr<CarCache> cars_;  // per-session parked cars, drawn on first use
};

}  // namespace loopscan::sim
