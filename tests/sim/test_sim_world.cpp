// Synthetic street world: determinism, a clear road, analytic primitives, revisits, seasons and
// sessions.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "loopscan/sim/world.hpp"

namespace ls = loopscan::sim;
using Eigen::Vector3d;

namespace {

// Points every `step` metres along straight legs through the corners.
std::vector<Vector3d> polyline(const std::vector<Vector3d>& corners, double step = 1.0) {
  std::vector<Vector3d> out{corners.front()};
  for (std::size_t i = 1; i < corners.size(); ++i) {
    const Vector3d d = corners[i] - corners[i - 1];
    const int n = static_cast<int>(std::ceil(d.norm() / step));
    for (int k = 1; k <= n; ++k) out.push_back(corners[i - 1] + d * (double(k) / n));
  }
  return out;
}

// A block with a crossing street and a loop closure (the first 100 m are driven twice).
std::vector<Vector3d> city_route() {
  return polyline(
      {{0, 0, 0}, {0, 0, 200}, {150, 0, 200}, {150, 0, 0}, {0, 0, 0}, {0, 0, 100}, {150, 0, 100}});
}

double distance_to_path(const std::vector<Vector3d>& path, const Vector3d& p) {
  double best = 1e300;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const Eigen::Vector2d a(path[i].x(), path[i].z()), b(path[i + 1].x(), path[i + 1].z());
    const Eigen::Vector2d q(p.x(), p.z()), e = b - a;
    const double s = std::clamp((q - a).dot(e) / std::max(e.squaredNorm(), 1e-12), 0.0, 1.0);
    best = std::min(best, (q - (a + s * e)).norm());
  }
  return best;
}

struct Ray {
  Vector3d o, d;
};

// Rays from centreline points (camera height) in random directions, `down` biased toward ground.
std::vector<Ray> random_rays(const std::vector<Vector3d>& path, int n, unsigned seed,
                             double lift = 0.0, double min_dy = -0.6, double max_dy = 0.3) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Ray> rays;
  for (int i = 0; i < n; ++i) {
    const Vector3d o = path[rng() % path.size()] + Vector3d(0, -lift, 0);
    const double yaw = 2 * M_PI * u(rng), dy = min_dy + (max_dy - min_dy) * u(rng);
    rays.push_back({o, Vector3d(std::cos(yaw), dy, std::sin(yaw)).normalized()});
  }
  return rays;
}

bool same_hit(const std::optional<ls::Hit>& a, const std::optional<ls::Hit>& b) {
  if (!a || !b) return !a && !b;
  return std::memcmp(&a->distance, &b->distance, sizeof(double)) == 0 && a->point == b->point &&
         a->surface == b->surface && a->object_id == b->object_id &&
         std::memcmp(&a->albedo, &b->albedo, sizeof(double)) == 0 &&
         std::memcmp(&a->texture_gradient, &b->texture_gradient, sizeof(double)) == 0;
}

bool is_ground(ls::Surface s) {
  return s == ls::Surface::Ground || s == ls::Surface::Road || s == ls::Surface::Sidewalk;
}

}  // namespace

TEST(SimWorld, SeasonsAndConditions) {
  for (const auto* name : {"spring", "summer", "fall", "winter"})
    EXPECT_EQ(ls::season_name(ls::parse_season(name)), name);
  EXPECT_THROW(ls::parse_season("autumn"), std::invalid_argument);
  EXPECT_THROW(ls::parse_season("Summer"), std::invalid_argument);
  const auto winter = ls::Conditions::for_season(ls::Season::Winter);
  EXPECT_EQ(winter.season, ls::Season::Winter);
  EXPECT_LT(winter.illumination_gain,
            ls::Conditions::for_season(ls::Season::Summer).illumination_gain);
  ls::Hit h;
  h.albedo = 0.5;
  ls::Conditions c;
  c.illumination_gain = 1.2;
  c.gamma = 2.0;
  EXPECT_NEAR(ls::World::gray(h, c), 255.0 * 0.36, 1e-9);
  h.albedo = 0.95;  // saturates
  EXPECT_DOUBLE_EQ(ls::World::gray(h, c), 255.0);
}

TEST(SimWorld, BuildIsDeterministic) {
  const auto path = city_route();
  ls::WorldConfig cfg;
  cfg.seed = 42;
  const auto a = ls::World::build(path, cfg), b = ls::World::build(path, cfg);
  EXPECT_EQ(a.parameters().dump(), b.parameters().dump());
  EXPECT_GT(a.object_count(), 50u);
  const auto cond = ls::Conditions::for_season(ls::Season::Fall);
  int hits = 0;
  for (const auto& r : random_rays(path, 3000, 5, 0.0, -0.6, 0.6)) {
    const auto ha = a.raycast(r.o, r.d, 120.0, cond), hb = b.raycast(r.o, r.d, 120.0, cond);
    ASSERT_TRUE(same_hit(ha, hb));
    hits += ha && !is_ground(ha->surface);
  }
  EXPECT_GT(hits, 500);
  cfg.seed = 43;  // another seed is another world
  EXPECT_NE(ls::World::build(path, cfg).parameters()["digest"], a.parameters()["digest"]);
}

TEST(SimWorld, NothingOnTheRoad) {
  const auto path = city_route();
  ls::WorldConfig cfg;
  const auto world = ls::World::build(path, cfg);
  const ls::Conditions cond;
  int objects = 0;
  // Horizontal rays 0.5 m above the ground, then rays in all directions from the camera.
  auto rays = random_rays(path, 6000, 11, -(cfg.camera_height_m - 0.5), 0.0, 0.0);
  for (const auto& r : random_rays(path, 4000, 12, 0.0, -1.0, 1.5)) rays.push_back(r);
  for (const auto& r : rays) {
    const auto hit = world.raycast(r.o, r.d, 150.0, cond);
    if (!hit) continue;
    if (hit->distance < cfg.road_half_width_m - 0.15) {
      EXPECT_TRUE(hit->surface == ls::Surface::Ground || hit->surface == ls::Surface::Road);
    }
    if (is_ground(hit->surface)) continue;
    ++objects;
    EXPECT_GE(distance_to_path(path, hit->point), cfg.road_half_width_m - 0.15)
        << ls::surface_name(hit->surface) << " at " << hit->point.transpose();
  }
  EXPECT_GT(objects, 2000);
}

TEST(SimWorld, PrimitivesGiveAnalyticDistances) {
  const ls::Box box = ls::make_box(3, 20, 0.4, 2.0, 1.0, -6.0, 1.65);
  const Vector3d v(-std::sin(0.4), 0, std::cos(0.4));  // the box's v axis in (x, y, z)
  const Vector3d o = Vector3d(3, 0, 20) + 10 * v;
  double t;
  int face;
  ASSERT_TRUE(ls::intersect_box(box, o, -v, 100, t, face));
  EXPECT_NEAR(t, 9.0, 1e-12);
  EXPECT_EQ(face, ls::kPlusV);
  EXPECT_FALSE(ls::intersect_box(box, o, v, 100, t, face));
  EXPECT_FALSE(ls::intersect_box(box, o, -v, 8.9, t, face));  // beyond max distance
  const ls::Cylinder cyl{-4, 7, 0.5, -8, 1.65};
  bool cap;
  ASSERT_TRUE(ls::intersect_cylinder(cyl, {-14, 0, 7.3}, {1, 0, 0}, 100, t, cap));
  EXPECT_NEAR(t, 10 - std::sqrt(0.25 - 0.09), 1e-12);
  EXPECT_FALSE(cap);
  ASSERT_TRUE(ls::intersect_cylinder(cyl, {-4.2, -20, 7}, {0, 1, 0}, 100, t, cap));
  EXPECT_NEAR(t, 12.0, 1e-12);
  EXPECT_TRUE(cap);
  const ls::Ellipsoid sphere{1, 2, 30, 2, 2};
  const Vector3d c(1, 2, 30);
  double t0, t1;
  ASSERT_TRUE(ls::intersect_ellipsoid(sphere, Vector3d::Zero(), c.normalized(), t0, t1));
  EXPECT_NEAR(t0, c.norm() - 2, 1e-12);
  EXPECT_NEAR(t1, c.norm() + 2, 1e-12);
  const ls::Ellipsoid spheroid{0, -5, 0, 1.5, 3};
  ASSERT_TRUE(ls::intersect_ellipsoid(spheroid, {0, -20, 0}, {0, 1, 0}, t0, t1));
  EXPECT_NEAR(t0, 12.0, 1e-12);

  // The same through a World: street along z at y = 0, ground at y = 1.65.
  const auto path = polyline({{0, 0, 0}, {0, 0, 100}});
  ls::ExplicitPrimitives prims;
  prims.facades.push_back(ls::make_box(12, 50, 0.0, 2.0, 2.0, -8.0, 1.65));
  prims.poles.push_back({-8, 50, 0.2, -6, 1.65});
  const auto world = ls::World::from_primitives(path, {}, prims);
  EXPECT_EQ(world.object_count(), 2u);
  const ls::Conditions cond;
  const auto check = [&](Vector3d from, Vector3d dir, double dist, ls::Surface s, int id) {
    const auto hit = world.raycast(from, dir, 200, cond);
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(hit->distance, dist, 1e-9);
    EXPECT_EQ(hit->surface, s);
    EXPECT_EQ(hit->object_id, id);
  };
  check({0, 0, 50}, {1, 0, 0}, 10.0, ls::Surface::Facade, 0);
  check({0, 0, 50}, {-1, 0, 0}, 7.8, ls::Surface::Pole, 1);
  check({12, -30, 50}, {0, 1, 0}, 22.0, ls::Surface::Roof, 0);
  check({0, 0, 30}, {0, 1, 0}, 1.65, ls::Surface::Road, -1);
  check({5.5, 0, 30}, {0, 1, 0}, 1.65, ls::Surface::Sidewalk, -1);
  check({9.0, 0, 30}, {0, 1, 0}, 1.65, ls::Surface::Ground, -1);
  EXPECT_FALSE(world.raycast({0, 0, 50}, {0, -1, 0}, 200, cond).has_value());  // sky
  EXPECT_FALSE(world.raycast({0, 0, 50}, {1, 0, 0}, 9.5, cond).has_value());
}

TEST(SimWorld, GroundFollowsTheCentreline) {
  // A street climbing 10 m over 200 m (y down: y decreases uphill).
  std::vector<Vector3d> path;
  for (int i = 0; i <= 200; ++i) path.emplace_back(0, -0.05 * i, i);
  const auto world = ls::World::from_primitives(path, {}, {});
  const auto hit = world.raycast({0, -5.0, 100}, {0, 1, 0}, 50, ls::Conditions{});
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->point.y(), -5.0 + 1.65, 1e-9);
  const Vector3d d = Vector3d(0, 0.1, 1).normalized();  // looking down the slope ahead
  const auto ahead = world.raycast({0, -5.0 + 1e-3, 100}, d, 200, ls::Conditions{});
  ASSERT_TRUE(ahead.has_value());
  EXPECT_NEAR(ahead->point.y(), -0.05 * ahead->point.z() + 1.65, 0.05);
}

TEST(SimWorld, RevisitedStreetsAddNothing) {
  const auto out = polyline({{0, 0, 0}, {0, 0, 200}, {120, 0, 200}});
  auto out_back = out;
  out_back.insert(out_back.end(), out.rbegin() + 1, out.rend());
  const auto loop = polyline({{0, 0, 0}, {0, 0, 160}, {120, 0, 160}, {120, 0, 0}, {0, 0, 0}});
  auto twice = loop;
  twice.insert(twice.end(), loop.begin() + 1, loop.end());
  for (const auto& [once, again] : {std::pair{out, out_back}, std::pair{loop, twice}}) {
    const auto a = ls::World::build(once, {}), b = ls::World::build(again, {});
    EXPECT_GT(a.object_count(), 30u);
    EXPECT_EQ(a.object_count(), b.object_count());
    EXPECT_EQ(a.parameters()["counts"], b.parameters()["counts"]);
    EXPECT_EQ(a.parameters()["digest"], b.parameters()["digest"]);
  }
}

TEST(SimWorld, WinterThinsFoliageAndAddsSnow) {
  const auto path = city_route();
  const auto world = ls::World::build(path, {});
  const auto summer = ls::Conditions::for_season(ls::Season::Summer);
  const auto winter = ls::Conditions::for_season(ls::Season::Winter);
  int crowns[2] = {0, 0}, roofs = 0, sidewalks = 0;
  double roof_albedo[2] = {0, 0};
  auto rays = random_rays(path, 6000, 21, 0.0, -0.8, 0.2);
  for (const auto& r : random_rays(path, 3000, 22, 40.0, 0.4, 3.0)) rays.push_back(r);  // drone
  for (const auto& r : rays) {
    const auto s = world.raycast(r.o, r.d, 150, summer), w = world.raycast(r.o, r.d, 150, winter);
    crowns[0] += s && s->surface == ls::Surface::Crown;
    crowns[1] += w && w->surface == ls::Surface::Crown;
    if (!s || s->surface == ls::Surface::Crown) continue;
    // Winter branches are a subset of summer leaves: everything else is the same geometry.
    ASSERT_TRUE(w.has_value());
    EXPECT_EQ(s->distance, w->distance);
    EXPECT_EQ(s->object_id, w->object_id);
    ASSERT_EQ(s->surface, w->surface);
    if (s->surface == ls::Surface::Roof) {
      ++roofs;
      roof_albedo[0] += s->albedo;
      roof_albedo[1] += w->albedo;
    }
    if (s->surface == ls::Surface::Sidewalk) {
      ++sidewalks;
      EXPECT_GT(w->albedo, 0.85);
      EXPECT_LT(s->albedo, 0.7);
    }
    if (s->surface == ls::Surface::Road || s->surface == ls::Surface::Facade ||
        s->surface == ls::Surface::Car) {
      EXPECT_EQ(s->albedo, w->albedo);  // the road is cleared, facades and cars unchanged
    }
  }
  EXPECT_GT(crowns[0], 100);
  EXPECT_LT(crowns[1], crowns[0] / 4);
  ASSERT_GT(roofs, 50);
  ASSERT_GT(sidewalks, 50);
  EXPECT_LT(roof_albedo[0] / roofs, 0.6);
  EXPECT_GT(roof_albedo[1] / roofs, 0.85);
}

TEST(SimWorld, SessionSeedRedrawsOnlyCars) {
  const auto path = city_route();
  const auto world = ls::World::build(path, {});
  ls::Conditions one, two;
  two.session_seed = 2;
  int cars = 0, changed = 0;
  for (const auto& r : random_rays(path, 6000, 31, 0.0, -0.3, 0.1)) {
    const auto a = world.raycast(r.o, r.d, 100, one), b = world.raycast(r.o, r.d, 100, two);
    ASSERT_TRUE(same_hit(a, world.raycast(r.o, r.d, 100, one)));  // stable within a session
    if (!a || !b) continue;
    const bool car = a->surface == ls::Surface::Car || b->surface == ls::Surface::Car;
    cars += a->surface == ls::Surface::Car;
    if (car) {
      changed += !same_hit(a, b);
      continue;
    }
    EXPECT_TRUE(same_hit(a, b)) << ls::surface_name(a->surface);
  }
  EXPECT_GT(cars, 100);
  EXPECT_GT(changed, 50);
}

namespace {

// The open road: guard rails stand beside both road edges along the whole route, and the road
// carries dashed lane lines half a lane off the centreline and solid edge lines.
TEST(SimWorld, OpenRoadHasGuardRailsAndLaneMarkings) {
  const ls::WorldConfig c = ls::open_road_world_config();
  const std::vector<Vector3d> path = polyline({{0, 0, 0}, {0, 0, 200}});
  const ls::World world = ls::World::build(path, c);
  EXPECT_GE(world.parameters()["counts"]["guard_rails"].get<int>(), 2 * 200 / 8);
  const ls::Conditions summer = ls::Conditions::for_season(ls::Season::Summer);
  // Sideways at beam height (0.6 m above the ground) from the centreline: the rail's face.
  const double rail = c.road_half_width_m + c.guard_rail_offset_m;
  for (const double z : {20.0, 101.0, 180.0})
    for (const double side : {-1.0, 1.0}) {
      const Vector3d o(0, c.camera_height_m - 0.6, z);
      const auto hit = world.raycast(o, Vector3d(side, 0, 0), 100.0, summer);
      ASSERT_TRUE(hit) << z;
      EXPECT_EQ(hit->surface, ls::Surface::Rail);
      EXPECT_NEAR(hit->distance, rail, 1e-6);
    }
  // Straight down onto the road: paint on the lane lines' dashes and on the edge lines only.
  const auto albedo_at = [&](double x, double z) {
    const auto hit = world.raycast(Vector3d(x, 0, z), Vector3d(0, 1, 0), 10.0, summer);
    EXPECT_TRUE(hit && hit->surface == ls::Surface::Road) << x << " " << z;
    return hit ? hit->albedo : 0.0;
  };
  const double lane = c.lane_width_m, edge = c.road_half_width_m - 0.35;
  for (const double z : {36.0 + 1.0, 36.0 + 5.0}) {  // inside a 6 m dash of the 18 m period
    EXPECT_GT(albedo_at(0.5 * lane, z), 0.7);
    EXPECT_GT(albedo_at(-1.5 * lane, z), 0.7);
  }
  EXPECT_LT(albedo_at(0.5 * lane, 36.0 + 12.0), 0.3);  // in the gap
  EXPECT_LT(albedo_at(lane, 37.0), 0.3);               // mid-lane
  for (const double z : {37.0, 48.0}) EXPECT_GT(albedo_at(edge, z), 0.7);
  // The default world has neither.
  const ls::World city = ls::World::build(path, ls::WorldConfig{});
  EXPECT_EQ(city.parameters()["counts"]["guard_rails"].get<int>(), 0);
  const auto plain = city.raycast(Vector3d(0.5 * lane, 0, 37.0), Vector3d(0, 1, 0), 10.0, summer);
  ASSERT_TRUE(plain);
  EXPECT_LT(plain->albedo, 0.3);
}

}  // namespace
