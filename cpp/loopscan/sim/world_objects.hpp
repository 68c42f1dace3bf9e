#pragma once
// The static content of a World (built once from the centreline) and the per-session cars.
#include <cstdint>
#include <vector>

#include "loopscan/sim/texture.hpp"
#include "loopscan/sim/world_centreline.hpp"
#include "loopscan/sim/world_config.hpp"
#include "loopscan/sim/world_grid.hpp"
#include "loopscan/sim/world_primitives.hpp"

namespace loopscan::sim {

struct FacadeObject {  // buildings and guard rails
  Box box;             // a building's flat top is its roof
  Surface surface = Surface::Facade;
  FacadeStyle style;
  double ground_y = 0.0;  // facade texture heights are measured from here
  int id = -1;
};

struct PostObject {  // trunks and poles
  Cylinder cylinder;
  Surface surface = Surface::Pole;
  double albedo = 0.5;
  double ground_y = 0.0;
  std::uint32_t salt = 0;
  int id = -1;
};

struct CrownObject {  // volumetric foliage: voxels inside the ellipsoid hold leaves per season
  Ellipsoid ellipsoid;
  int id = -1;
};

struct CarSlot {  // a parking place; whether and which car stands there depends on the session
  Box area;       // the largest footprint a car (with its jitter) may cover, for the grid
  double cx = 0.0, cz = 0.0, yaw = 0.0;
  double ground_y = 0.0;
  int id = -1;
};

struct ParkedCar {
  bool present = false;
  Box box;
  CarStyle style;
};

enum class ObjectKind : std::uint32_t { Facade = 0, Post = 1, Crown = 2, CarSlot = 3 };

inline std::uint32_t grid_code(ObjectKind kind, std::size_t index) {
  return (static_cast<std::uint32_t>(kind) << 28) | static_cast<std::uint32_t>(index);
}
inline ObjectKind code_kind(std::uint32_t code) { return static_cast<ObjectKind>(code >> 28); }
inline std::size_t code_index(std::uint32_t code) { return code & 0x0fffffffU; }

struct StaticWorld {
  WorldConfig config;
  std::vector<FacadeObject> facades;
  std::vector<PostObject> posts;
  std::vector<CrownObject> crowns;
  std::vector<CarSlot> slots;
  CentrelineIndex centreline;
  ObjectGrid grid;
  bool flat = true;  // all centreline samples at one height: the ground is a single plane
  double flat_ground_y = 0.0;
  // Texture salts drawn from the world's mt19937.
  std::uint32_t ground_salt = 0, roof_salt = 0, foliage_salt = 0, leaf_salt = 0;
  // Statistics for World::parameters().
  std::size_t input_points = 0, street_samples = 0, used_samples = 0, runs = 0;
  std::size_t trees = 0, poles = 0, guard_rails = 0;
  bool explicit_primitives = false;
};

// Ground height (y) under (x, z): camera_height below the nearest centreline point.
double ground_y_at(const StaticWorld& world, double x, double z);
// Lays out facades, trees, poles and car slots along the first visit of every street.
void layout_streets(const std::vector<Eigen::Vector3d>& centreline, StaticWorld& world);
// Builds the acceleration grid once the objects are in place.
void finish_world(StaticWorld& world);
// The cars parked in every slot during one session (deterministic in both seeds).
std::vector<ParkedCar> draw_parked_cars(const StaticWorld& world, unsigned session_seed);

}  // namespace loopscan::sim
