#pragma once
// Internals of World shared by world.cpp, world_raycast.cpp and world_shading.cpp.
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

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

// Surface, albedo (season applied) and texture gradient of each kind of hit.
Hit shade_ground(const StaticWorld& w, const Eigen::Vector3d& p, double t, const Conditions& c);
Hit shade_facade(const StaticWorld& w, const FacadeObject& f, int face, const Eigen::Vector3d& p,
                 double t, const Conditions& c);
Hit shade_post(const PostObject& post, bool cap, const Eigen::Vector3d& p, double t);
Hit shade_crown(const StaticWorld& w, const CrownObject& crown, const Eigen::Vector3d& p, double t,
                const Conditions& c);
Hit shade_car(const ParkedCar& car, int id, int face, const Eigen::Vector3d& p, double t);

}  // namespace loopscan::sim
