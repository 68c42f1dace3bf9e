// Parked cars of one session, and the acceleration grid over the static objects.
#include <cmath>

#include "loopscan/sim/world_layout.hpp"

namespace loopscan::sim {

std::vector<ParkedCar> draw_parked_cars(const StaticWorld& world, unsigned session_seed) {
  std::seed_seq seq{static_cast<std::uint32_t>(world.config.seed),
                    static_cast<std::uint32_t>(session_seed), 0xCA25U};
  std::mt19937 rng(seq);
  static constexpr double kPalette[] = {0.08, 0.85, 0.55, 0.35, 0.3, 0.22, 0.62};
  std::vector<ParkedCar> cars(world.slots.size());
  for (std::size_t i = 0; i < world.slots.size(); ++i) {
    const CarSlot& slot = world.slots[i];
    // A fixed number of draws per slot: slot i's car does not depend on the other slots.
    const bool present = chance(rng, world.config.car_occupancy);
    CarStyle st;
    st.length = uniform(rng, 3.8, 4.9);
    st.width = uniform(rng, 1.65, 1.9);
    st.height = uniform(rng, 1.35, 1.75);
    const double along = uniform(rng, -0.4, 0.4);
    const double across = uniform(rng, -0.1, 0.1);
    const double yaw = slot.yaw + uniform(rng, -0.03, 0.03);
    st.front_at_plus_u = chance(rng, 0.5);
    const auto colour = static_cast<std::size_t>(uniform(rng, 0.0, 7.0));
    st.body = kPalette[colour < 7 ? colour : 6] + uniform(rng, -0.04, 0.04);
    st.glass = uniform(rng, 0.06, 0.16);
    st.salt = static_cast<std::uint32_t>(rng());
    if (!present) continue;
    const double c0 = std::cos(slot.yaw), s0 = std::sin(slot.yaw);
    ParkedCar& car = cars[i];
    car.present = true;
    car.style = st;
    car.box = make_box(slot.cx + along * c0 - across * s0, slot.cz + along * s0 + across * c0, yaw,
                       0.5 * st.length, 0.5 * st.width, slot.ground_y - st.height, slot.ground_y);
  }
  return cars;
}

void finish_world(StaticWorld& world) {
  std::vector<GridItem> items;
  for (std::size_t i = 0; i < world.facades.size(); ++i) {
    const Box& b = world.facades[i].box;
    items.push_back(
        {footprint_bounds(box_footprint(b)), b.y_top, grid_code(ObjectKind::Facade, i)});
  }
  for (std::size_t i = 0; i < world.posts.size(); ++i) {
    const Cylinder& c = world.posts[i].cylinder;
    items.push_back({footprint_bounds(disc_footprint(c.cx, c.cz, c.radius)), c.y_top,
                     grid_code(ObjectKind::Post, i)});
  }
  for (std::size_t i = 0; i < world.crowns.size(); ++i) {
    const Ellipsoid& e = world.crowns[i].ellipsoid;
    items.push_back({footprint_bounds(disc_footprint(e.cx, e.cz, e.radius_h)), e.cy - e.radius_v,
                     grid_code(ObjectKind::Crown, i)});
  }
  for (std::size_t i = 0; i < world.slots.size(); ++i) {
    const Box& b = world.slots[i].area;
    items.push_back(
        {footprint_bounds(box_footprint(b)), b.y_top, grid_code(ObjectKind::CarSlot, i)});
  }
  world.grid = ObjectGrid(items, world.config.grid_cell_m);
}

}  // namespace loopscan::sim
