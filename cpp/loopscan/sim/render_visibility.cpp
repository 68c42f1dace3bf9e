#include "loopscan/sim/render_visibility.hpp"

#include <algorithm>
#include <cmath>

namespace loopscan::sim {
namespace {

// An object's bounds as an upright box rotated about the vertical (axis-aligned: cos 1, sin 0).
struct Bounds {
  double cx, cz, cos_yaw, sin_yaw, half_u, half_v, y0, y1;
};

Bounds box_bounds(const Box& b) {
  return {b.cx, b.cz, b.cos_yaw, b.sin_yaw, b.half_u, b.half_v, b.y_top, b.y_bottom};
}

bool object_bounds(const StaticWorld& w, const std::vector<ParkedCar>& cars, std::uint32_t code,
                   Bounds& out) {
  const std::size_t i = code_index(code);
  switch (code_kind(code)) {
    case ObjectKind::Facade:
      out = box_bounds(w.facades[i].box);
      return true;
    case ObjectKind::Post: {
      const Cylinder& c = w.posts[i].cylinder;
      out = {c.cx, c.cz, 1.0, 0.0, c.radius, c.radius, c.y_top, c.y_bottom};
      return true;
    }
    case ObjectKind::Crown: {
      const Ellipsoid& e = w.crowns[i].ellipsoid;
      out = {e.cx, e.cz, 1.0, 0.0, e.radius_h, e.radius_h, e.cy - e.radius_v, e.cy + e.radius_v};
      return true;
    }
    case ObjectKind::CarSlot:
      if (!cars[i].present) return false;
      out = box_bounds(cars[i].box);
      return true;
  }
  return false;
}

// Distance from the point to the box (0 inside).
double distance_to(const Bounds& b, const Eigen::Vector3d& p) {
  const double dx = p.x() - b.cx, dz = p.z() - b.cz;
  const double u = dx * b.cos_yaw + dz * b.sin_yaw, v = -dx * b.sin_yaw + dz * b.cos_yaw;
  const double eu = std::max(std::abs(u) - b.half_u, 0.0);
  const double ev = std::max(std::abs(v) - b.half_v, 0.0);
  const double ey = std::max({b.y0 - p.y(), p.y() - b.y1, 0.0});
  return std::sqrt(eu * eu + ev * ev + ey * ey);
}

struct PixelRect {
  double u0 = 1e300, v0 = 1e300, u1 = -1e300, v1 = -1e300;
  void add(const StereoCamera& c, const Eigen::Vector3d& q) {
    const double u = c.fx * q.x() / q.z() + c.cx, v = c.fy * q.y() / q.z() + c.cy;
    u0 = std::min(u0, u);
    u1 = std::max(u1, u);
    v0 = std::min(v0, v);
    v1 = std::max(v1, v);
  }
};

// Image rectangle of the box's part in front of the camera: its corners in front plus the
// crossings of its edges with a near plane (a convex body projects into their hull).
bool project_bounds(const Bounds& b, const StereoCamera& camera, const Eigen::Vector3d& origin,
                    const Eigen::Matrix3d& Rt, PixelRect& rect) {
  constexpr double kNear = 1e-6;
  Eigen::Vector3d q[8];
  for (int k = 0; k < 8; ++k) {
    const double su = (k & 1) ? b.half_u : -b.half_u, sv = (k & 2) ? b.half_v : -b.half_v;
    const Eigen::Vector3d p(b.cx + su * b.cos_yaw - sv * b.sin_yaw, (k & 4) ? b.y1 : b.y0,
                            b.cz + su * b.sin_yaw + sv * b.cos_yaw);
    q[k] = Rt * (p - origin);
  }
  for (int k = 0; k < 8; ++k) {
    if (q[k].z() >= kNear) rect.add(camera, q[k]);
    for (int bit = 1; bit < 8; bit <<= 1) {  // edges to the corners differing in one bit
      const int m = k | bit;
      if (m == k) continue;
      const double za = q[k].z(), zb = q[m].z();
      if ((za < kNear) == (zb < kNear)) continue;
      const double s = (kNear - za) / (zb - za);
      Eigen::Vector3d x = q[k] + s * (q[m] - q[k]);
      x.z() = kNear;
      rect.add(camera, x);
    }
  }
  return rect.u0 <= rect.u1;
}

}  // namespace

TileBins bin_view(const StaticWorld& world, const std::vector<ParkedCar>& cars,
                  const StereoCamera& camera, const Eigen::Vector3d& origin,
                  const Eigen::Matrix3d& R, double max_distance) {
  TileBins bins;
  const int K = TileBins::kTile;
  bins.tiles_x = (camera.width + K - 1) / K;
  bins.tiles_y = (camera.height + K - 1) / K;
  const std::size_t tiles = static_cast<std::size_t>(bins.tiles_x) * bins.tiles_y;
  // Objects of the grid cells within reach, each once (kinds are numbered after each other).
  const std::size_t offset[4] = {0, world.facades.size(), world.facades.size() + world.posts.size(),
                                 world.facades.size() + world.posts.size() + world.crowns.size()};
  std::vector<std::uint8_t> seen(offset[3] + world.slots.size(), 0);
  std::vector<ViewCandidate> in_view;
  const Eigen::Matrix3d Rt = R.transpose();
  const double margin = 0.5;  // pixels: rays are rounded, rectangles are generous
  world.grid.visit_rect(
      origin.x() - max_distance, origin.z() - max_distance, origin.x() + max_distance,
      origin.z() + max_distance, [&](std::uint32_t code) {
        std::uint8_t& s = seen[offset[static_cast<int>(code_kind(code))] + code_index(code)];
        if (s) return;
        s = 1;
        Bounds b;
        if (!object_bounds(world, cars, code, b)) return;
        const double d = distance_to(b, origin);
        if (d >= max_distance) return;
        ViewCandidate c;
        c.code = code;
        // Slightly below the true bound, so rounding in the ray tests cannot cut a hit off.
        c.min_distance = d * (1.0 - 1e-9) - 1e-9;
        if (d < 1e-3) {  // the camera is (nearly) inside: every pixel may see it
          c.u0 = c.v0 = 0;
          c.u1 = camera.width - 1;
          c.v1 = camera.height - 1;
        } else {
          PixelRect r;
          if (!project_bounds(b, camera, origin, Rt, r)) return;
          const auto lo = [](double a, int n) {
            return static_cast<std::int32_t>(std::clamp(std::ceil(a), -1.0, double(n)));
          };
          const auto hi = [](double a, int n) {
            return static_cast<std::int32_t>(std::clamp(std::floor(a), -1.0, double(n)));
          };
          c.u0 = std::max(lo(r.u0 - margin, camera.width), 0);
          c.u1 = std::min(hi(r.u1 + margin, camera.width), camera.width - 1);
          c.v0 = std::max(lo(r.v0 - margin, camera.height), 0);
          c.v1 = std::min(hi(r.v1 + margin, camera.height), camera.height - 1);
          if (c.u0 > c.u1 || c.v0 > c.v1) return;
        }
        in_view.push_back(c);
      });
  bins.objects = in_view.size();
  // Nearest first; the code breaks ties so the order never depends on the walk.
  std::sort(in_view.begin(), in_view.end(), [](const ViewCandidate& a, const ViewCandidate& b) {
    return a.min_distance != b.min_distance ? a.min_distance < b.min_distance : a.code < b.code;
  });
  // Count, then fill: each tile's list keeps the sorted order.
  std::vector<std::uint32_t> count(tiles + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) {
      bins.start.assign(tiles + 1, 0);
      for (std::size_t t = 0; t < tiles; ++t) bins.start[t + 1] = bins.start[t] + count[t];
      bins.items.resize(bins.start.back());
      std::fill(count.begin(), count.end(), 0);
    }
    for (const ViewCandidate& c : in_view)
      for (int ty = c.v0 / K; ty <= c.v1 / K; ++ty)
        for (int tx = c.u0 / K; tx <= c.u1 / K; ++tx) {
          const std::size_t t = static_cast<std::size_t>(ty) * bins.tiles_x + tx;
          if (pass == 1) bins.items[bins.start[t] + count[t]] = c;
          ++count[t];
        }
  }
  return bins;
}

}  // namespace loopscan::sim
