#include "loopscan/sim/world_config.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace loopscan::sim {

std::string surface_name(Surface surface) {
  switch (surface) {
    case Surface::Ground:
      return "ground";
    case Surface::Road:
      return "road";
    case Surface::Sidewalk:
      return "sidewalk";
    case Surface::Facade:
      return "facade";
    case Surface::Roof:
      return "roof";
    case Surface::Trunk:
      return "trunk";
    case Surface::Crown:
      return "crown";
    case Surface::Pole:
      return "pole";
    case Surface::Car:
      return "car";
    case Surface::Rail:
      return "rail";
  }
  return "unknown";
}

void WorldConfig::validate() const {
  const auto need = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("WorldConfig: ") + what);
  };
  need(road_half_width_m >= 0.0, "road_half_width_m must be >= 0");
  need(camera_height_m > 0.0, "camera_height_m must be > 0");
  need(sidewalk_width_m > 0.0, "sidewalk_width_m must be > 0");
  need(road_grain >= 0.0 && road_grain <= 1.0, "road_grain in [0, 1]");
  need(lane_width_m > 0.0, "lane_width_m must be > 0");
  need(guard_rail_offset_m >= 0.0, "guard_rail_offset_m must be >= 0");
  need(sample_spacing_m > 0.0, "sample_spacing_m must be > 0");
  need(revisit_radius_m > 0.0, "revisit_radius_m must be > 0");
  need(facade_width_min_m > 0.0 && facade_width_min_m <= facade_width_max_m, "facade width");
  need(facade_height_min_m > 0.0 && facade_height_min_m <= facade_height_max_m, "facade height");
  need(facade_depth_min_m > 0.0 && facade_depth_min_m <= facade_depth_max_m, "facade depth");
  need(setback_min_m >= 0.0 && setback_min_m <= setback_max_m, "setback");
  need(gap_probability >= 0.0 && gap_probability < 1.0, "gap_probability in [0, 1)");
  need(gap_width_min_m > 0.0 && gap_width_min_m <= gap_width_max_m, "gap width");
  need(tree_street_probability >= 0.0 && tree_street_probability <= 1.0,
       "tree_street_probability in [0, 1]");
  need(tree_spacing_min_m > 0.0 && tree_spacing_min_m <= tree_spacing_max_m, "tree spacing");
  need(crown_radius_min_m > 0.0 && crown_radius_min_m <= crown_radius_max_m, "crown radius");
  need(foliage_voxel_m > 0.0, "foliage_voxel_m must be > 0");
  need(pole_spacing_m > 0.0, "pole_spacing_m must be > 0");
  need(car_slot_spacing_m > 0.0, "car_slot_spacing_m must be > 0");
  need(car_occupancy >= 0.0 && car_occupancy <= 1.0, "car_occupancy in [0, 1]");
  need(grid_cell_m > 0.0, "grid_cell_m must be > 0");
  need(max_route_length_m > 0.0 && max_extent_m > 0.0, "route bounds must be > 0");
}

std::string route_size_problem(const std::vector<Eigen::Vector3d>& centreline,
                               const WorldConfig& config) {
  if (centreline.empty()) return "";
  double length = 0, largest_step = 0;
  std::size_t step_at = 0;
  Eigen::Vector3d lo = centreline.front(), hi = lo;
  for (std::size_t i = 0; i < centreline.size(); ++i) {
    const Eigen::Vector3d& p = centreline[i];
    if (!p.allFinite()) return "finite positions (frame " + std::to_string(i) + " is not)";
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
    if (i == 0) continue;
    const double step = (p - centreline[i - 1]).norm();
    length += step;
    if (step > largest_step) {
      largest_step = step;
      step_at = i;
    }
  }
  const Eigen::Vector3d size = hi - lo;
  const double extent = std::max(size.x(), size.z());  // the ground plane (y is down)
  char buf[320];
  if (length > config.max_route_length_m || extent > config.max_extent_m) {
    std::snprintf(buf, sizeof buf,
                  "a route of at most %.0f km spanning at most %.0f km (this one is %.1f km long "
                  "and spans %.1f km; its largest step is %.1f m, between frames %zu and %zu)",
                  config.max_route_length_m / 1e3, config.max_extent_m / 1e3, length / 1e3,
                  extent / 1e3, largest_step, step_at - 1, step_at);
    return buf;
  }
  return "";
}

WorldConfig open_road_world_config() {
  WorldConfig c;
  c.road_half_width_m = 11.0;
  c.sidewalk_width_m = 3.0;
  c.lane_markings = true;
  c.guard_rails = true;
  c.setback_min_m = 20.0;
  c.setback_max_m = 80.0;
  c.gap_probability = 0.6;
  c.gap_width_min_m = 20.0;
  c.gap_width_max_m = 80.0;
  c.tree_street_probability = 0.3;
  c.tree_spacing_min_m = 15.0;
  c.tree_spacing_max_m = 50.0;
  c.pole_spacing_m = 50.0;
  c.car_occupancy = 0.0;
  return c;
}

nlohmann::json to_json(const WorldConfig& c) {
  return {{"seed", c.seed},
          {"road_half_width_m", c.road_half_width_m},
          {"camera_height_m", c.camera_height_m},
          {"sidewalk_width_m", c.sidewalk_width_m},
          {"road_grain", c.road_grain},
          {"lane_markings", c.lane_markings},
          {"lane_width_m", c.lane_width_m},
          {"guard_rails", c.guard_rails},
          {"guard_rail_offset_m", c.guard_rail_offset_m},
          {"sample_spacing_m", c.sample_spacing_m},
          {"revisit_radius_m", c.revisit_radius_m},
          {"facade_width_m", {c.facade_width_min_m, c.facade_width_max_m}},
          {"facade_height_m", {c.facade_height_min_m, c.facade_height_max_m}},
          {"facade_depth_m", {c.facade_depth_min_m, c.facade_depth_max_m}},
          {"setback_m", {c.setback_min_m, c.setback_max_m}},
          {"gap_probability", c.gap_probability},
          {"gap_width_m", {c.gap_width_min_m, c.gap_width_max_m}},
          {"tree_street_probability", c.tree_street_probability},
          {"tree_spacing_m", {c.tree_spacing_min_m, c.tree_spacing_max_m}},
          {"crown_radius_m", {c.crown_radius_min_m, c.crown_radius_max_m}},
          {"foliage_voxel_m", c.foliage_voxel_m},
          {"pole_spacing_m", c.pole_spacing_m},
          {"car_slot_spacing_m", c.car_slot_spacing_m},
          {"car_occupancy", c.car_occupancy},
          {"grid_cell_m", c.grid_cell_m}};
}

}  // namespace loopscan::sim
