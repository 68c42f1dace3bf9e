#include "loopscan/sim/world.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "loopscan/sim/world_internal.hpp"

namespace loopscan::sim {
namespace {

// Centreline index, ground plane mode and texture salts: everything but the objects.
std::shared_ptr<StaticWorld> start_world(const std::vector<Eigen::Vector3d>& centreline,
                                         const WorldConfig& config) {
  config.validate();
  if (const std::string problem = route_size_problem(centreline, config); !problem.empty()) {
    throw std::invalid_argument("World: expected " + problem);
  }
  auto w = std::make_shared<StaticWorld>();
  w->config = config;
  w->input_points = centreline.size();
  w->centreline = CentrelineIndex(centreline, config.grid_cell_m);
  // A level city is one plane: the ground hit needs no nearest-centreline iteration.
  w->flat = w->centreline.empty() || w->centreline.max_y() - w->centreline.min_y() <= 1e-9;
  w->flat_ground_y = (w->centreline.empty() ? 0.0 : w->centreline.min_y()) + config.camera_height_m;
  std::seed_seq seq{static_cast<std::uint32_t>(config.seed), 0x5A175U};
  std::mt19937 rng(seq);
  w->ground_salt = static_cast<std::uint32_t>(rng());
  w->roof_salt = static_cast<std::uint32_t>(rng());
  w->foliage_salt = static_cast<std::uint32_t>(rng());
  w->leaf_salt = static_cast<std::uint32_t>(rng());
  return w;
}

// FNV-1a over the bit patterns of the geometry: equal digests <=> identical worlds (in practice).
class Digest {
 public:
  void add(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    for (int b = 0; b < 8; ++b) {
      h_ ^= (bits >> (8 * b)) & 0xffU;
      h_ *= 0x100000001b3ULL;
    }
  }
  void add(const Box& b) {
    for (double v : {b.cx, b.cz, b.cos_yaw, b.sin_yaw, b.half_u, b.half_v, b.y_top, b.y_bottom})
      add(v);
  }
  std::string hex() const {
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h_));
    return buf;
  }

 private:
  std::uint64_t h_ = 0xcbf29ce484222325ULL;
};

}  // namespace

World::World() = default;

World World::build(const std::vector<Eigen::Vector3d>& centreline, const WorldConfig& config) {
  auto w = start_world(centreline, config);
  layout_streets(centreline, *w);
  finish_world(*w);
  World out;
  out.world_ = w;
  out.cars_ = std::make_shared<CarCache>();
  return out;
}

World World::from_primitives(const std::vector<Eigen::Vector3d>& centreline,
                             const WorldConfig& config, const ExplicitPrimitives& primitives) {
  auto w = start_world(centreline, config);
  w->explicit_primitives = true;
  int id = 0;
  for (const Box& b : primitives.facades) {
    FacadeObject f;
    f.box = b;
    f.ground_y = b.y_bottom;
    f.style.salt = static_cast<std::uint32_t>(id);
    f.id = id++;
    w->facades.push_back(f);
  }
  for (const Cylinder& c : primitives.poles) {
    PostObject p;
    p.cylinder = c;
    p.ground_y = c.y_bottom;
    p.id = id++;
    w->posts.push_back(p);
    ++w->poles;
  }
  for (const Ellipsoid& e : primitives.crowns) w->crowns.push_back(CrownObject{e, id++});
  finish_world(*w);
  World out;
  out.world_ = w;
  out.cars_ = std::make_shared<CarCache>();
  return out;
}

std::size_t World::object_count() const {
  if (!world_) return 0;
  return world_->facades.size() + world_->posts.size() + world_->crowns.size();
}

nlohmann::json World::parameters() const {
  if (!world_) return {{"empty", true}};
  const StaticWorld& w = *world_;
  Digest digest;
  for (const auto& f : w.facades) {
    digest.add(f.box);
    for (double v : {f.style.wall, f.style.glass, f.style.floor_height, f.style.window_pitch})
      digest.add(v);
  }
  for (const auto& p : w.posts)
    for (double v : {p.cylinder.cx, p.cylinder.cz, p.cylinder.radius, p.cylinder.y_top,
                     p.cylinder.y_bottom, p.albedo})
      digest.add(v);
  for (const auto& c : w.crowns)
    for (double v : {c.ellipsoid.cx, c.ellipsoid.cy, c.ellipsoid.cz, c.ellipsoid.radius_h,
                     c.ellipsoid.radius_v})
      digest.add(v);
  for (const auto& s : w.slots) digest.add(s.area);
  nlohmann::json j;
  j["seed"] = w.config.seed;
  j["config"] = to_json(w.config);
  j["explicit_primitives"] = w.explicit_primitives;
  j["centreline"] = {{"input_points", w.input_points},
                     {"segments", w.centreline.segment_count()},
                     {"street_samples", w.street_samples},
                     {"used_samples", w.used_samples},
                     {"runs", w.runs},
                     {"flat", w.flat}};
  j["counts"] = {{"objects", object_count()},
                 {"facades", w.facades.size() - w.guard_rails},
                 {"trees", w.trees},
                 {"poles", w.poles},
                 {"guard_rails", w.guard_rails},
                 {"crowns", w.crowns.size()},
                 {"car_slots", w.slots.size()}};
  j["grid"] = {{"cell_m", w.grid.cell()},
               {"nx", w.grid.nx()},
               {"nz", w.grid.nz()},
               {"references", w.grid.references()}};
  j["texture_salts"] = {w.ground_salt, w.roof_salt, w.foliage_salt, w.leaf_salt};
  j["car_slot_first_id"] = w.slots.empty() ? -1 : w.slots.front().id;
  j["digest"] = digest.hex();
  return j;
}

}  // namespace loopscan::sim
