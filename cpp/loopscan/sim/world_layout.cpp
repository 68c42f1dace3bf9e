#include "loopscan/sim/world_layout.hpp"

#include <algorithm>
#include <cmath>

namespace loopscan::sim {
namespace {

Eigen::Vector2d xz(const Eigen::Vector3d& p) { return {p.x(), p.z()}; }

void close_run(Run& run, std::vector<Run>& runs) {
  if (run.pts.size() >= 2) {
    run.arc.assign(1, 0.0);
    for (std::size_t k = 1; k < run.pts.size(); ++k)
      run.arc.push_back(run.arc.back() + (run.pts[k] - run.pts[k - 1]).norm());
    runs.push_back(std::move(run));
  }
  run = Run{};
}

std::size_t segment_of(const Run& r, double s) {
  const auto it = std::upper_bound(r.arc.begin(), r.arc.end(), s);
  const std::size_t k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - r.arc.begin(), 1));
  return std::min(k, r.arc.size() - 1) - 1;  // segment k-1 .. k
}

}  // namespace

Eigen::Vector2d Run::point_at(double s) const {
  const std::size_t k = segment_of(*this, s);
  return pts[k] + (s - arc[k]) * tangent_at(s);
}

Eigen::Vector2d Run::tangent_at(double s) const {
  const std::size_t k = segment_of(*this, s);
  return (pts[k + 1] - pts[k]).normalized();
}

std::vector<Run> street_runs(const std::vector<Eigen::Vector3d>& centreline, const WorldConfig& c,
                             std::size_t& n_samples, std::size_t& n_used) {
  const auto samples = resample_path(centreline, c.sample_spacing_m);
  n_samples = samples.size();
  n_used = 0;
  std::vector<Run> runs;
  if (samples.empty()) return runs;
  const double r = c.revisit_radius_m;
  // Dense grid of used samples over the samples' bounding box (cells of the revisit radius).
  double min_x = 1e300, min_z = 1e300, max_x = -1e300, max_z = -1e300;
  for (const auto& p : samples) {
    min_x = std::min(min_x, p.x());
    min_z = std::min(min_z, p.z());
    max_x = std::max(max_x, p.x());
    max_z = std::max(max_z, p.z());
  }
  const int nx = static_cast<int>((max_x - min_x) / r) + 1;
  const int nz = static_cast<int>((max_z - min_z) / r) + 1;
  std::vector<std::vector<std::size_t>> used(static_cast<std::size_t>(nx) * nz);
  const double exempt = r + c.sample_spacing_m;  // recent samples of the same pass never block
  Run run;
  std::size_t last_used = samples.size();
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const int ci = static_cast<int>((samples[i].x() - min_x) / r);
    const int cj = static_cast<int>((samples[i].z() - min_z) / r);
    bool revisit = false;
    for (int j = std::max(cj - 1, 0); j <= std::min(cj + 1, nz - 1) && !revisit; ++j)
      for (int k = std::max(ci - 1, 0); k <= std::min(ci + 1, nx - 1) && !revisit; ++k)
        for (const std::size_t u : used[static_cast<std::size_t>(j) * nx + k]) {
          const double arc_gap = static_cast<double>(i - u) * c.sample_spacing_m;
          if (arc_gap > exempt && (xz(samples[i]) - xz(samples[u])).norm() < r) {
            revisit = true;
            break;
          }
        }
    if (revisit) {
      close_run(run, runs);
      continue;
    }
    used[static_cast<std::size_t>(cj) * nx + ci].push_back(i);
    ++n_used;
    const Eigen::Vector2d p = xz(samples[i]);
    const bool continues = last_used + 1 == i && !run.pts.empty();
    // A U-turn ends the run: the way back is laid out (or ignored) on its own.
    const bool reverses = continues && run.pts.size() >= 2 &&
                          (run.pts.back() - run.pts[run.pts.size() - 2]).dot(p - run.pts.back()) <
                              -0.5 * (run.pts.back() - run.pts[run.pts.size() - 2]).norm() *
                                  (p - run.pts.back()).norm();
    if (!continues || reverses) close_run(run, runs);
    run.pts.push_back(p);
    last_used = i;
  }
  close_run(run, runs);
  return runs;
}

void FootprintHash::insert(const Footprint& f, int tag) {
  const int index = static_cast<int>(entries_.size());
  entries_.emplace_back(f, tag);
  const Eigen::Vector4d b = footprint_bounds(f);
  for (int j = static_cast<int>(std::floor(b[1] / cell_)); j <= std::floor(b[3] / cell_); ++j)
    for (int i = static_cast<int>(std::floor(b[0] / cell_)); i <= std::floor(b[2] / cell_); ++i)
      cells_[key(i, j)].push_back(index);
}

bool FootprintHash::overlaps(const Footprint& f, double margin, int tag_mask) const {
  const Eigen::Vector4d b = footprint_bounds(f);
  const double m = std::max(margin, 0.0);
  for (int j = static_cast<int>(std::floor((b[1] - m) / cell_));
       j <= std::floor((b[3] + m) / cell_); ++j)
    for (int i = static_cast<int>(std::floor((b[0] - m) / cell_));
         i <= std::floor((b[2] + m) / cell_); ++i) {
      const auto it = cells_.find(key(i, j));
      if (it == cells_.end()) continue;
      for (const int e : it->second)
        if ((entries_[e].second & tag_mask) != 0 &&
            footprints_overlap(f, entries_[e].first, margin))
          return true;
    }
  return false;
}

Eigen::Vector2d Layout::beside(const Run& run, double s, double side, double offset) const {
  const Eigen::Vector2d t = run.tangent_at(s);
  return run.point_at(s) + side * offset * Eigen::Vector2d(-t.y(), t.x());
}

bool Layout::clear_of_road(const Footprint& f) const {
  const double rhw = world.config.road_half_width_m;
  return world.centreline.distance_to(f, rhw) >= rhw;
}

double ground_y_at(const StaticWorld& world, double x, double z) {
  if (world.flat) return world.flat_ground_y;
  const auto n = world.centreline.nearest(x, z);
  return (n.found ? n.y : 0.0) + world.config.camera_height_m;
}

void place_facades(Layout& L, std::mt19937& rng) {
  const WorldConfig& c = L.world.config;
  for (const Run& run : L.runs)
    for (const double side : {1.0, -1.0}) {
      double s = -uniform(rng, 0.0, 6.0);  // streets start with a building, not always aligned
      while (s < run.length() + 3.0) {
        // Every draw happens for every slot, so one rejection does not shift the others.
        const bool gap = chance(rng, c.gap_probability);
        const double gap_w = uniform(rng, c.gap_width_min_m, c.gap_width_max_m);
        const double w = uniform(rng, c.facade_width_min_m, c.facade_width_max_m);
        const double depth = uniform(rng, c.facade_depth_min_m, c.facade_depth_max_m);
        const double height = uniform(rng, c.facade_height_min_m, c.facade_height_max_m);
        const double setback = uniform(rng, c.setback_min_m, c.setback_max_m);
        const double spacing = uniform(rng, 0.0, 0.6);
        FacadeStyle st;
        st.wall = uniform(rng, 0.3, 0.75);
        st.glass = uniform(rng, 0.06, 0.22);
        st.frame = st.wall > 0.55 ? uniform(rng, 0.12, 0.3) : uniform(rng, 0.65, 0.9);
        st.floor_height = uniform(rng, 2.8, 3.5);
        st.ground_floor_height = uniform(rng, 3.2, 4.5);
        st.window_pitch = uniform(rng, 2.2, 3.6);
        st.window_width = uniform(rng, 0.9, std::min(1.8, st.window_pitch - 0.6));
        st.window_height = uniform(rng, 1.2, std::min(1.9, st.floor_height - 1.1));
        st.sill = std::min(uniform(rng, 0.7, 1.0), st.floor_height - st.window_height - 0.3);
        st.brick = chance(rng, 0.35);
        st.shop_front = chance(rng, 0.4);
        st.salt = static_cast<std::uint32_t>(rng());
        if (gap) {
          s += gap_w;
          continue;
        }
        const Eigen::Vector2d a = run.point_at(s), b = run.point_at(s + w);
        s += w + spacing;
        const double len = (b - a).norm();
        if (len < 1.0) continue;
        const Eigen::Vector2d u = (b - a) / len;
        const Eigen::Vector2d n = side * Eigen::Vector2d(-u.y(), u.x());
        const double front = c.road_half_width_m + c.sidewalk_width_m + setback;
        const Eigen::Vector2d mid = 0.5 * (a + b) + (front + 0.5 * depth) * n;
        const double g = ground_y_at(L.world, mid.x(), mid.y());
        FacadeObject f;
        // Foundations reach 1 m below the local ground so sloped streets show no gaps.
        f.box = Box{mid.x(), mid.y(), u.x(), u.y(), 0.5 * len, 0.5 * depth, g - height, g + 1.0};
        f.style = st;
        f.ground_y = g;
        const Footprint fp = box_footprint(f.box);
        if (!L.clear_of_road(fp) || L.occupied.overlaps(fp, -0.5, kTagFacade)) continue;
        f.id = L.next_id++;
        L.occupied.insert(fp, kTagFacade);
        L.world.facades.push_back(f);
      }
    }
}

// Street furniture along the runs: trees and poles on the outer edge of the sidewalk, parking
// slots in the lane next to the road.
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
            L.occupied.overlaps(trunk_fp, 0.3, kTagFacade | kTagRail | kTagTrunk | kTagPole) ||
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
        if (!L.clear_of_road(fp) ||
            L.occupied.overlaps(fp, 0.8, kTagFacade | kTagRail | kTagTrunk | kTagPole))
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
            L.occupied.overlaps(fp, 0.1, kTagFacade | kTagRail | kTagTrunk | kTagPole) ||
            L.occupied.overlaps(fp, 0.0, kTagSlot))
          continue;
        slot.id = L.next_id++;
        L.occupied.insert(fp, kTagSlot);
        L.world.slots.push_back(slot);
      }
    }
}

void place_guard_rails(Layout& L, std::mt19937& rng) {
  const WorldConfig& c = L.world.config;
  if (!c.guard_rails) return;
  constexpr double kPiece = 8.0, kHalfDepth = 0.15;  // a multiple of the 2 m post pitch
  const double offset = c.road_half_width_m + c.guard_rail_offset_m + kHalfDepth;
  for (const Run& run : L.runs)
    for (const double side : {1.0, -1.0})
      for (double s = 0.0; s < run.length(); s += kPiece) {
        const std::uint32_t salt = static_cast<std::uint32_t>(rng());
        const double e = std::min(s + kPiece, run.length());
        const Eigen::Vector2d a = L.beside(run, s, side, offset),
                              b = L.beside(run, e, side, offset);
        const double len = (b - a).norm();
        if (len < 0.5) continue;
        const Eigen::Vector2d u = (b - a) / len, mid = 0.5 * (a + b);
        const double g = ground_y_at(L.world, mid.x(), mid.y());
        FacadeObject rail;
        // Pieces overlap by 5 cm so that bends leave no slits.
        rail.box =
            Box{mid.x(), mid.y(), u.x(), u.y(), 0.5 * len + 0.05, kHalfDepth, g - kGuardRailHeight,
                g + 0.2};
        rail.surface = Surface::Rail;
        rail.style.salt = salt;
        rail.ground_y = g;
        const Footprint fp = box_footprint(rail.box);
        if (!L.clear_of_road(fp) || L.occupied.overlaps(fp, 0.0, kTagFacade)) continue;
        rail.id = L.next_id++;
        L.occupied.insert(fp, kTagRail);
        L.world.facades.push_back(rail);
        ++L.world.guard_rails;
      }
}

void layout_streets(const std::vector<Eigen::Vector3d>& centreline, StaticWorld& world) {
  const WorldConfig& c = world.config;
  world.input_points = centreline.size();
  const auto runs = street_runs(centreline, c, world.street_samples, world.used_samples);
  world.runs = runs.size();
  Layout layout{world, runs, FootprintHash(25.0), 0};
  // One generator per object class: tuning one class leaves the others unchanged.
  const auto stage = [&](std::uint32_t tag) {
    std::seed_seq seq{static_cast<std::uint32_t>(c.seed), tag};
    return std::mt19937(seq);
  };
  auto facade_rng = stage(0xFACADE);
  place_facades(layout, facade_rng);
  auto rail_rng = stage(0x2A11);
  place_guard_rails(layout, rail_rng);
  auto tree_rng = stage(0x7EE5);
  place_trees(layout, tree_rng);
  auto pole_rng = stage(0x901E5);
  place_poles(layout, pole_rng);
  auto slot_rng = stage(0xCA2);
  place_car_slots(layout, slot_rng);
}

}  // namespace loopscan::sim
