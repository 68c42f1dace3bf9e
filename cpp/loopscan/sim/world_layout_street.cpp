// Street furniture along the runs: trees and poles on the outer edge of the sidewalk, parking
// slots in the lane next to the road.
#include <cmath>

#include "loopscan/sim/world_layout.hpp"

namespace loopscan::sim {
namespace {

// Trees and poles stand 0.3 m inside the outer edge of the sidewalk.
double furniture_offset(const WorldConfig& c) {
  return c.road_half_width_m + c.sidewalk_width_m - 0.3;
}

constexpr double kSlotHalfLength = 2.9;  // longest car 4.9 m plus +-0.4 m along-slot jitter
constexpr double kSlotHalfWidth = 1.12;  // widest car 1.9 m plus lateral/yaw jitter
constexpr double kSlotMaxHeight = 2.0;

}  // namespace

void place_trees(Layout& L, std::mt19937& rng) {
  const WorldConfig& c = L.world.config;
  for (const Run& run : L.runs)
    for (const double side : {1.0, -1.0}) {
      bool lined = false;
      double stretch_end = -1.0;  // a run spans several streets: lining changes along it
      double s = uniform(rng, 0.0, c.tree_spacing_min_m);
      while (s < run.length()) {
        if (s >= stretch_end) {
          lined = chance(rng, c.tree_street_probability);
          stretch_end = s + uniform(rng, 60.0, 160.0);
        }
        const double trunk_r = uniform(rng, 0.12, 0.25);
        const double crown_h = uniform(rng, c.crown_radius_min_m, c.crown_radius_max_m);
        const double crown_v = crown_h * uniform(rng, 0.9, 1.5);
        const double base = uniform(rng, 2.2, 3.5);  // crown bottom above the ground
        const double bark = uniform(rng, 0.18, 0.32);
        const std::uint32_t salt = static_cast<std::uint32_t>(rng());
        const double next = uniform(rng, c.tree_spacing_min_m, c.tree_spacing_max_m);
        const Eigen::Vector2d p = L.beside(run, s, side, furniture_offset(c));
        s += next;
        if (!lined) continue;
        const double g = ground_y_at(L.world, p.x(), p.y());
        const Footprint trunk_fp = disc_footprint(p.x(), p.y(), trunk_r);
        const Footprint crown_fp = disc_footprint(p.x(), p.y(), crown_h);
        if (!L.clear_of_road(crown_fp) ||
            L.occupied.overlaps(trunk_fp, 0.3, kTagFacade | kTagTrunk | kTagPole) ||
            L.occupied.overlaps(crown_fp, -0.5, kTagFacade))
          continue;
        CrownObject crown;
        crown.ellipsoid = Ellipsoid{p.x(), g - base - crown_v, p.y(), crown_h, crown_v};
        PostObject trunk;
        // The trunk reaches the crown's centre: visible through the bare winter crown.
        trunk.cylinder = Cylinder{p.x(), p.y(), trunk_r, crown.ellipsoid.cy, g + 0.5};
        trunk.surface = Surface::Trunk;
        trunk.albedo = bark;
        trunk.ground_y = g;
        trunk.salt = salt;
        trunk.id = L.next_id++;
        crown.id = L.next_id++;
        L.occupied.insert(trunk_fp, kTagTrunk);
        L.occupied.insert(crown_fp, kTagCrown);
        L.world.posts.push_back(trunk);
        L.world.crowns.push_back(crown);
        ++L.world.trees;
      }
    }
}

void place_poles(Layout& L, std::mt19937& rng) {
  const WorldConfig& c = L.world.config;
  for (const Run& run : L.runs)
    for (const double side : {1.0, -1.0}) {
      double s = uniform(rng, 0.0, c.pole_spacing_m);
      while (s < run.length()) {
        const double r = uniform(rng, 0.08, 0.12);
        const double height = uniform(rng, 6.0, 9.0);
        const double albedo = uniform(rng, 0.4, 0.65);
        const std::uint32_t salt = static_cast<std::uint32_t>(rng());
        const double next = c.pole_spacing_m * uniform(rng, 0.8, 1.2);
        const Eigen::Vector2d p = L.beside(run, s, side, furniture_offset(c));
        s += next;
        const Footprint fp = disc_footprint(p.x(), p.y(), r);
        if (!L.clear_of_road(fp) || L.occupied.overlaps(fp, 0.8, kTagFacade | kTagTrunk | kTagPole))
          continue;
        const double g = ground_y_at(L.world, p.x(), p.y());
        PostObject pole;
        pole.cylinder = Cylinder{p.x(), p.y(), r, g - height, g + 0.5};
        pole.surface = Surface::Pole;
        pole.albedo = albedo;
        pole.ground_y = g;
        pole.salt = salt;
        pole.id = L.next_id++;
        L.occupied.insert(fp, kTagPole);
        L.world.posts.push_back(pole);
        ++L.world.poles;
      }
    }
}

void place_car_slots(Layout& L, std::mt19937& rng) {
  const WorldConfig& c = L.world.config;
  const double lane = c.road_half_width_m + 0.13 + kSlotHalfWidth;  // slot edge 13 cm off the road
  for (const Run& run : L.runs)
    for (const double side : {1.0, -1.0}) {
      double s = uniform(rng, 0.0, 0.5 * c.car_slot_spacing_m);
      for (; s < run.length(); s += c.car_slot_spacing_m) {
        const Eigen::Vector2d p = L.beside(run, s, side, lane);
        const Eigen::Vector2d t = run.tangent_at(s);
        const double g = ground_y_at(L.world, p.x(), p.y());
        CarSlot slot;
        slot.cx = p.x();
        slot.cz = p.y();
        slot.yaw = std::atan2(t.y(), t.x());
        slot.ground_y = g;
        slot.area =
            Box{p.x(), p.y(), t.x(), t.y(), kSlotHalfLength, kSlotHalfWidth, g - kSlotMaxHeight, g};
        const Footprint fp = box_footprint(slot.area);
        if (!L.clear_of_road(fp) ||
            L.occupied.overlaps(fp, 0.1, kTagFacade | kTagTrunk | kTagPole) ||
            L.occupied.overlaps(fp, 0.0, kTagSlot))
          continue;
        slot.id = L.next_id++;
        L.occupied.insert(fp, kTagSlot);
        L.world.slots.push_back(slot);
      }
    }
}

}  // namespace loopscan::sim
