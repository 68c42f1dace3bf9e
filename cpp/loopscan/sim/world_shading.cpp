// Albedo and texture gradient at a hit, with the season's effects (snow, foliage colour).
#include <cmath>

#include "loopscan/core/simd.hpp"
#include "loopscan/sim/texture_noise.hpp"
#include "loopscan/sim/world_internal.hpp"

namespace loopscan::sim {
namespace {

// The per-kind shaders are inlined into both entry points (shade_hit, shade_albedo): in the
// albedo-only one the compiler then drops everything else a Hit holds.
LOOPSCAN_INLINE Hit make_hit(double t, const Eigen::Vector3d& p, Surface s,
                             const TextureSample& tex, int id) {
  Hit h;
  h.distance = t;
  h.point = p;
  h.surface = s;
  h.albedo = tex.albedo;
  h.texture_gradient = tex.gradient;
  h.object_id = id;
  return h;
}

// Spring grass is fresher (lighter), fall grass is dry and strewn with leaves.
double grass_shift(Season s) { return s == Season::Spring ? 0.05 : s == Season::Fall ? 0.08 : 0.0; }

LOOPSCAN_INLINE Hit shade_ground(const StaticWorld& w, const Eigen::Vector3d& p, double t,
                                 const Conditions& c, bool g) {
  return shade_ground_as(w, ground_surface(w, w.centreline.nearest(p.x(), p.z()).distance), p, t, c,
                         g);
}

LOOPSCAN_INLINE Hit shade_guard_rail(const FacadeObject& f, int face, const Eigen::Vector3d& p,
                                     double t, bool g) {
  if (face == kTop) return make_hit(t, p, Surface::Rail, TextureSample{0.5, 0.0}, f.id);
  double lu, lv;
  box_local(f.box, p.x(), p.z(), lu, lv);
  const bool across_u = face == kMinusU || face == kPlusU;
  const double u = across_u ? lv : lu;
  const auto albedo = [&](double uu, double vv) { return guard_rail_albedo(f.style.salt, uu, vv); };
  return make_hit(t, p, Surface::Rail, sample_surface(albedo, u, f.ground_y - p.y(), g), f.id);
}

LOOPSCAN_INLINE Hit shade_facade(const StaticWorld& w, const FacadeObject& f, int face,
                                 const Eigen::Vector3d& p, double t, const Conditions& c, bool g) {
  if (f.surface == Surface::Rail) return shade_guard_rail(f, face, p, t, g);
  if (face == kTop) {
    const std::uint32_t salt = w.roof_salt;
    const bool snow = has_snow(c.season);
    const auto albedo = [&](double x, double z) {
      return snow ? snow_albedo(salt + 3, x, z)
                  : roof_albedo(salt + static_cast<std::uint32_t>(f.id), x, z);
    };
    return make_hit(t, p, Surface::Roof, sample_surface(albedo, p.x(), p.z(), g), f.id);
  }
  double lu, lv;
  box_local(f.box, p.x(), p.z(), lu, lv);
  // Faces across u run along v and vice versa; heights are measured from the ground.
  const bool across_u = face == kMinusU || face == kPlusU;
  const double u = across_u ? lv + f.box.half_v : lu + f.box.half_u;
  const double width = 2.0 * (across_u ? f.box.half_v : f.box.half_u);
  const double height = f.ground_y - f.box.y_top;
  const auto albedo = [&](double uu, double vv) {
    return facade_albedo(f.style, uu, vv, width, height);
  };
  return make_hit(t, p, Surface::Facade, sample_surface(albedo, u, f.ground_y - p.y(), g), f.id);
}

LOOPSCAN_INLINE Hit shade_post(const PostObject& post, bool cap, const Eigen::Vector3d& p, double t,
                               bool g) {
  if (post.surface == Surface::Pole || cap)  // poles are plain paint; cut trunk tops too
    return make_hit(t, p, post.surface, TextureSample{post.albedo, 0.0}, post.id);
  const Cylinder& c = post.cylinder;
  const double u = std::atan2(p.z() - c.cz, p.x() - c.cx) * c.radius;  // arc length
  // Unwrap near the seam (atan2 jumps by 2 pi r) so the finite differences stay local.
  const double seam = 3.14159265358979 * c.radius;
  const auto albedo = [&](double uu, double vv) {
    double x = uu;
    if (x > seam) x -= 2.0 * seam;
    if (x < -seam) x += 2.0 * seam;
    return bark_albedo(post.salt, post.albedo, x, vv);
  };
  return make_hit(t, p, Surface::Trunk, sample_surface(albedo, u, post.ground_y - p.y(), g),
                  post.id);
}

LOOPSCAN_INLINE Hit shade_crown(const StaticWorld& w, const CrownObject& crown,
                                const Eigen::Vector3d& p, double t, const Conditions& c, bool g) {
  const double base = foliage_albedo(c.season);
  const std::uint32_t salt = w.leaf_salt;
  const auto albedo = [&](double x, double y, double z) {
    return leaf_albedo(salt, base, x, y, z);
  };
  return make_hit(t, p, Surface::Crown, sample_volume(albedo, p.x(), p.y(), p.z(), g), crown.id);
}

LOOPSCAN_INLINE Hit shade_car(const ParkedCar& car, int id, int face, const Eigen::Vector3d& p,
                              double t, bool g) {
  double lu, lv;
  box_local(car.box, p.x(), p.z(), lu, lv);
  const CarStyle& s = car.style;
  const double up = car.box.y_bottom - p.y();  // height above the ground
  TextureSample tex;
  if (face == kTop || face == kBottom) {
    tex = sample_surface([&](double a, double b) { return car_roof_albedo(s, a, b); }, lu, lv, g);
  } else if (face == kMinusV || face == kPlusV) {
    tex = sample_surface([&](double a, double b) { return car_side_albedo(s, a, b); },
                         lu + car.box.half_u, up, g);
  } else {
    const bool front = (face == kPlusU) == s.front_at_plus_u;
    tex = sample_surface([&](double a, double b) { return car_end_albedo(s, a, b, front); },
                         lv + car.box.half_v, up, g);
  }
  return make_hit(t, p, Surface::Car, tex, id);
}

}  // namespace

Surface ground_surface(const StaticWorld& w, double centreline_distance) {
  const double rhw = w.config.road_half_width_m;
  if (centreline_distance < rhw) return Surface::Road;
  return centreline_distance < rhw + w.config.sidewalk_width_m ? Surface::Sidewalk
                                                               : Surface::Ground;
}

namespace {

LOOPSCAN_INLINE Hit shade_ground_as_inline(const StaticWorld& w, Surface s,
                                           const Eigen::Vector3d& p, double t, const Conditions& c,
                                           bool g) {
  const std::uint32_t salt = w.ground_salt;
  if (s == Surface::Road) {  // the road is cleared of snow
    const WorldConfig& wc = w.config;
    const auto albedo = [&](double x, double z) {
      const double asphalt = road_albedo(salt, x, z, wc.road_grain);
      if (!wc.lane_markings) return asphalt;
      constexpr double kPaint = 0.75;  // worn white paint
      const CentrelineIndex::Nearest n = w.centreline.nearest(x, z);
      if (!n.found) return asphalt;
      const double paint = lane_marking(n.distance, w.centreline.arc_length(n.segment, x, z),
                                        wc.road_half_width_m, wc.lane_width_m);
      return asphalt + (kPaint - asphalt) * paint;
    };
    return make_hit(t, p, Surface::Road, sample_surface(albedo, p.x(), p.z(), g), -1);
  }
  const bool snow = has_snow(c.season);
  const double shift = grass_shift(c.season);
  const auto albedo = [&](double x, double z) {
    if (snow) return snow_albedo(salt + 17, x, z);
    if (s == Surface::Sidewalk) return sidewalk_albedo(salt + 29, x, z);
    return std::fmin(1.0, grass_albedo(salt + 41, x, z) + shift);
  };
  return make_hit(t, p, s, sample_surface(albedo, p.x(), p.z(), g), -1);
}

LOOPSCAN_INLINE Hit shade_hit_inline(const StaticWorld& w, const HitRef& ref,
                                     const Eigen::Vector3d& o, const Eigen::Vector3d& d, double t,
                                     const std::vector<ParkedCar>* cars, const Conditions& c,
                                     bool gradient) {
  const Eigen::Vector3d p = o + t * d;
  if (ref.ground) return shade_ground(w, p, t, c, gradient);
  const std::size_t i = code_index(ref.code);
  switch (code_kind(ref.code)) {
    case ObjectKind::Facade:
      return shade_facade(w, w.facades[i], ref.face, p, t, c, gradient);
    case ObjectKind::Post:
      return shade_post(w.posts[i], ref.cap, p, t, gradient);
    case ObjectKind::Crown:
      return shade_crown(w, w.crowns[i], p, t, c, gradient);
    case ObjectKind::CarSlot:
      break;
  }
  return shade_car((*cars)[i], w.slots[i].id, ref.face, p, t, gradient);
}

}  // namespace

Hit shade_ground_as(const StaticWorld& w, Surface s, const Eigen::Vector3d& p, double t,
                    const Conditions& c, bool g) {
  return shade_ground_as_inline(w, s, p, t, c, g);
}

LOOPSCAN_SIM_CLONES double ground_albedo_as(const StaticWorld& w, Surface s,
                                            const Eigen::Vector3d& p, const Conditions& c) {
  return shade_ground_as_inline(w, s, p, 0.0, c, false).albedo;
}

Hit shade_hit(const StaticWorld& w, const HitRef& ref, const Eigen::Vector3d& o,
              const Eigen::Vector3d& d, double t, const std::vector<ParkedCar>* cars,
              const Conditions& c, bool gradient) {
  return shade_hit_inline(w, ref, o, d, t, cars, c, gradient);
}

LOOPSCAN_SIM_CLONES double shade_albedo(const StaticWorld& w, const HitRef& ref,
                                        const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                        double t, const std::vector<ParkedCar>* cars,
                                        const Conditions& c) {
  return shade_hit_inline(w, ref, o, d, t, cars, c, false).albedo;
}

}  // namespace loopscan::sim
