#include "loopscan/sim/world_primitives.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "loopscan/sim/texture_noise.hpp"  // LOOPSCAN_SIM_CLONES

namespace loopscan::sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Clips [t_in, t_out] by the slab lo <= o + t d <= hi; records which side was entered/left.
bool clip_slab(double o, double d, double lo, double hi, double& t_in, double& t_out, int axis,
               int& face_in, int& face_out) {
  if (std::abs(d) < 1e-300) return o >= lo && o <= hi;  // parallel: inside or never
  double a = (lo - o) / d, b = (hi - o) / d;
  int fa = axis * 2, fb = axis * 2 + 1;
  if (a > b) {
    std::swap(a, b);
    std::swap(fa, fb);
  }
  if (a > t_in) {
    t_in = a;
    face_in = fa;
  }
  if (b < t_out) {
    t_out = b;
    face_out = fb;
  }
  return t_in <= t_out;
}

double point_rect_distance(double u, double v, double hu, double hv) {
  return std::hypot(std::max(std::abs(u) - hu, 0.0), std::max(std::abs(v) - hv, 0.0));
}

double point_segment_distance(double px, double pz, double ax, double az, double bx, double bz) {
  const double ex = bx - ax, ez = bz - az, len2 = ex * ex + ez * ez;
  double s = len2 > 0.0 ? ((px - ax) * ex + (pz - az) * ez) / len2 : 0.0;
  s = std::clamp(s, 0.0, 1.0);
  return std::hypot(px - (ax + s * ex), pz - (az + s * ez));
}

}  // namespace

Box make_box(double cx, double cz, double yaw, double half_u, double half_v, double y_top,
             double y_bottom) {
  return Box{cx, cz, std::cos(yaw), std::sin(yaw), half_u, half_v, y_top, y_bottom};
}

LOOPSCAN_SIM_CLONES bool intersect_box(const Box& b, const Eigen::Vector3d& o,
                                       const Eigen::Vector3d& d, double t_max, double& t,
                                       int& face) {
  double lu, lv;
  box_local(b, o.x(), o.z(), lu, lv);
  const double du = d.x() * b.cos_yaw + d.z() * b.sin_yaw;
  const double dv = -d.x() * b.sin_yaw + d.z() * b.cos_yaw;
  double t_in = -kInf, t_out = kInf;
  int face_in = -1, face_out = -1;
  if (!clip_slab(lu, du, -b.half_u, b.half_u, t_in, t_out, 0, face_in, face_out)) return false;
  if (!clip_slab(o.y(), d.y(), b.y_top, b.y_bottom, t_in, t_out, 1, face_in, face_out))
    return false;
  if (!clip_slab(lv, dv, -b.half_v, b.half_v, t_in, t_out, 2, face_in, face_out)) return false;
  if (t_in >= 0.0) {
    if (t_in >= t_max || face_in < 0) return false;
    t = t_in;
    face = face_in;
    return true;
  }
  if (t_out < 0.0 || t_out >= t_max || face_out < 0) return false;
  t = t_out;  // origin inside: the exit is the first surface
  face = face_out;
  return true;
}

bool intersect_cylinder(const Cylinder& c, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                        double t_max, double& t, bool& cap) {
  const double px = o.x() - c.cx, pz = o.z() - c.cz;
  const double a = d.x() * d.x() + d.z() * d.z();
  const double cc = px * px + pz * pz - c.radius * c.radius;
  double t_in = -kInf, t_out = kInf;
  if (a < 1e-300) {
    if (cc > 0.0) return false;  // vertical ray outside the disc
  } else {
    const double bh = px * d.x() + pz * d.z();
    const double disc = bh * bh - a * cc;
    if (disc < 0.0) return false;
    const double sq = std::sqrt(disc);
    t_in = (-bh - sq) / a;
    t_out = (-bh + sq) / a;
  }
  int face_in = 0, face_out = 0;  // 0: side, 2/3: caps (slab faces of axis 1)
  if (!clip_slab(o.y(), d.y(), c.y_top, c.y_bottom, t_in, t_out, 1, face_in, face_out))
    return false;
  if (t_in >= 0.0) {
    if (t_in >= t_max) return false;
    t = t_in;
    cap = face_in != 0;
    return true;
  }
  if (t_out < 0.0 || t_out >= t_max) return false;
  t = t_out;
  cap = face_out != 0;
  return true;
}

LOOPSCAN_SIM_CLONES bool intersect_ellipsoid(const Ellipsoid& e, const Eigen::Vector3d& o,
                                             const Eigen::Vector3d& d, double& t0, double& t1) {
  // Scale y so the spheroid becomes a sphere of radius radius_h; t is unchanged.
  const double s = e.radius_h / e.radius_v;
  const double px = o.x() - e.cx, py = (o.y() - e.cy) * s, pz = o.z() - e.cz;
  const double dx = d.x(), dy = d.y() * s, dz = d.z();
  const double a = dx * dx + dy * dy + dz * dz;
  const double bh = px * dx + py * dy + pz * dz;
  const double c = px * px + py * py + pz * pz - e.radius_h * e.radius_h;
  const double disc = bh * bh - a * c;
  if (a <= 0.0 || disc < 0.0) return false;
  const double sq = std::sqrt(disc);
  t0 = (-bh - sq) / a;
  t1 = (-bh + sq) / a;
  return t1 >= 0.0;
}

Footprint box_footprint(const Box& b) {
  Footprint f;
  f.cx = b.cx;
  f.cz = b.cz;
  f.cos_yaw = b.cos_yaw;
  f.sin_yaw = b.sin_yaw;
  f.half_u = b.half_u;
  f.half_v = b.half_v;
  return f;
}

Footprint disc_footprint(double cx, double cz, double radius) {
  Footprint f;
  f.cx = cx;
  f.cz = cz;
  f.radius = radius;
  f.disc = true;
  return f;
}

Eigen::Vector4d footprint_bounds(const Footprint& f) {
  if (f.disc) return {f.cx - f.radius, f.cz - f.radius, f.cx + f.radius, f.cz + f.radius};
  const double ex = std::abs(f.cos_yaw) * f.half_u + std::abs(f.sin_yaw) * f.half_v;
  const double ez = std::abs(f.sin_yaw) * f.half_u + std::abs(f.cos_yaw) * f.half_v;
  return {f.cx - ex, f.cz - ez, f.cx + ex, f.cz + ez};
}

double footprint_segment_distance(const Footprint& f, double ax, double az, double bx, double bz) {
  if (f.disc) return std::max(0.0, point_segment_distance(f.cx, f.cz, ax, az, bx, bz) - f.radius);
  // Work in the rectangle's frame: segment inside/crossing -> 0, else endpoint/corner distances.
  const auto local = [&](double x, double z, double& u, double& v) {
    const double dx = x - f.cx, dz = z - f.cz;
    u = dx * f.cos_yaw + dz * f.sin_yaw;
    v = -dx * f.sin_yaw + dz * f.cos_yaw;
  };
  double au, av, bu, bv;
  local(ax, az, au, av);
  local(bx, bz, bu, bv);
  double t_in = 0.0, t_out = 1.0;
  int fi = 0, fo = 0;
  if (clip_slab(au, bu - au, -f.half_u, f.half_u, t_in, t_out, 0, fi, fo) &&
      clip_slab(av, bv - av, -f.half_v, f.half_v, t_in, t_out, 2, fi, fo))
    return 0.0;
  double best = std::min(point_rect_distance(au, av, f.half_u, f.half_v),
                         point_rect_distance(bu, bv, f.half_u, f.half_v));
  for (const double su : {-1.0, 1.0})
    for (const double sv : {-1.0, 1.0})
      best = std::min(best, point_segment_distance(su * f.half_u, sv * f.half_v, au, av, bu, bv));
  return best;
}

bool footprints_overlap(const Footprint& a, const Footprint& b, double margin) {
  if (a.disc && b.disc) return std::hypot(a.cx - b.cx, a.cz - b.cz) < a.radius + b.radius + margin;
  if (a.disc || b.disc) {
    const Footprint& disc = a.disc ? a : b;
    const Footprint& rect = a.disc ? b : a;
    return footprint_segment_distance(rect, disc.cx, disc.cz, disc.cx, disc.cz) <
           disc.radius + margin;
  }
  // Separating axis test over the four edge normals.
  const double dx = b.cx - a.cx, dz = b.cz - a.cz;
  const double axes[4][2] = {{a.cos_yaw, a.sin_yaw},
                             {-a.sin_yaw, a.cos_yaw},
                             {b.cos_yaw, b.sin_yaw},
                             {-b.sin_yaw, b.cos_yaw}};
  for (const auto& ax : axes) {
    const auto radius = [&](const Footprint& f) {
      return f.half_u * std::abs(f.cos_yaw * ax[0] + f.sin_yaw * ax[1]) +
             f.half_v * std::abs(-f.sin_yaw * ax[0] + f.cos_yaw * ax[1]);
    };
    if (std::abs(dx * ax[0] + dz * ax[1]) >= radius(a) + radius(b) + margin) return false;
  }
  return true;
}

}  // namespace loopscan::sim
