#pragma once
// Parameters of the synthetic street world and the surface classes a ray can hit.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

namespace loopscan::sim {

enum class Surface { Ground, Road, Sidewalk, Facade, Roof, Trunk, Crown, Pole, Car, Rail };
std::string surface_name(Surface surface);

// Cross-section of a street (distances from the centreline): road up to road_half_width, then
// the parking lane (cars) and sidewalk (trees and poles on its outer edge) up to
// road_half_width + sidewalk_width, then the setback, then the buildings.
struct WorldConfig {
  unsigned seed = 1;
  double road_half_width_m = 4.5;  // nothing (except ground) within this distance of the centreline
  double camera_height_m = 1.65;
  double sidewalk_width_m = 3.0;

  // Road surface: the asphalt's fine grain (albedo amplitude) and, for open roads, lane
  // markings: dashed lines between lanes of lane_width_m (the camera drives mid-lane), a solid
  // line along each edge.
  double road_grain = 0.025;
  bool lane_markings = false;
  double lane_width_m = 3.5;

  // Street sampling: objects are laid out once per street even if the trajectory revisits it.
  double sample_spacing_m = 4.0;
  double revisit_radius_m = 6.0;

  // Buildings.
  double facade_width_min_m = 6.0, facade_width_max_m = 25.0;
  double facade_height_min_m = 5.0, facade_height_max_m = 25.0;
  double facade_depth_min_m = 8.0, facade_depth_max_m = 20.0;
  double setback_min_m = 1.0, setback_max_m = 6.0;  // beyond the sidewalk
  double gap_probability = 0.2;
  double gap_width_min_m = 3.0, gap_width_max_m = 15.0;

  // Trees on the sidewalk.
  double tree_street_probability = 0.85;  // share of street sides lined with trees
  double tree_spacing_min_m = 8.0, tree_spacing_max_m = 15.0;
  double crown_radius_min_m = 1.5, crown_radius_max_m = 2.4;
  double foliage_voxel_m = 0.25;  // leaf clusters: crowns are voxelised, density per season

  // Guard rails along both road edges (highways), guard_rail_offset_m beyond the road's edge.
  bool guard_rails = false;
  double guard_rail_offset_m = 0.5;

  // Street lights.
  double pole_spacing_m = 25.0;

  // Parked cars: static slots, occupancy redrawn per session.
  double car_slot_spacing_m = 6.0;
  double car_occupancy = 0.5;

  double grid_cell_m = 10.0;  // ray-casting acceleration grid

  // Bounds on the route a world is built along (time and memory grow with both): far above
  // any real drive (KITTI 00-10 < 4 km and 1 km across, RobotCar ~10 km and 2 km across).
  double max_route_length_m = 100e3;
  double max_extent_m = 20e3;  // each side of the route's bounding box

  void validate() const;  // throws std::invalid_argument on inconsistent values
};

// Why a world along `centreline` would exceed config's bounds (route length, extent, non-finite
// points), naming the largest step between consecutive points; empty when it would not.
std::string route_size_problem(const std::vector<Eigen::Vector3d>& centreline,
                               const WorldConfig& config);

// An open road (motorway): a 22 m carriageway with lane markings and guard rails, a grass verge,
// sparse trees and lights, buildings far off and often missing, no parked cars. Structure is
// mostly far away: the stereo VO's hard case (docs/vo.md). docs/experiments/open-road.yaml holds
// the same settings for the CLI.
WorldConfig open_road_world_config();

nlohmann::json to_json(const WorldConfig& config);

}  // namespace loopscan::sim
