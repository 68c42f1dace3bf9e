#pragma once
// Per-view visibility lists for the renderer. Every object near the camera is projected once
// (a conservative pixel rectangle and the nearest distance any of its points can have) and
// binned into small pixel tiles, each tile's list sorted by that distance. A pixel then tests
// only its tile's objects, nearest first, and stops once the next one cannot beat its hit:
// the same nearest hit as the grid walk of World::raycast, with far fewer tests per ray.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "loopscan/sim/camera.hpp"
#include "loopscan/sim/world_objects.hpp"

namespace loopscan::sim {

struct ViewCandidate {
  double min_distance = 0.0;  // lower bound of the ray parameter of any hit on the object
  std::int32_t u0 = 0, v0 = 0, u1 = -1, v1 = -1;  // pixels it may cover (inclusive)
  std::uint32_t code = 0;                         // grid code of the object
};

struct TileBins {
  static constexpr int kTile = 8;  // pixels a side
  int tiles_x = 0, tiles_y = 0;
  std::vector<std::uint32_t> start;  // CSR offsets per tile (row-major), tiles_x * tiles_y + 1
  std::vector<ViewCandidate> items;  // per tile, ascending min_distance
  std::size_t objects = 0;           // distinct objects in view
};

// origin: camera centre, R: camera-to-world rotation (both world frame); objects farther than
// max_distance and absent parked cars are left out.
TileBins bin_view(const StaticWorld& world, const std::vector<ParkedCar>& cars,
                  const StereoCamera& camera, const Eigen::Vector3d& origin,
                  const Eigen::Matrix3d& R, double max_distance);

}  // namespace loopscan::sim
