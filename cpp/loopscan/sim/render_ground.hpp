#pragma once
// Per-row caches of the renderer's centreline queries, the cost of every ground pixel: a
// nearest-segment search for the road / sidewalk / ground class and, on streets that are not
// level, for the height of the ground under each step of the ray's iteration.
#include <cmath>
#include <cstdint>
#include <vector>

#include "loopscan/sim/world_internal.hpp"

namespace loopscan::sim {

// nearest() for points near each other. A point within kShift of the anchor (the last full
// query, at nearest distance D) has its nearest segment within D + kShift of itself, so within
// D + 2 kShift of the anchor: those segments answer it exactly. They are gathered when a second
// point comes that close (far ground moves more than that from pixel to pixel).
class NearestCache {
 public:
  explicit NearestCache(const CentrelineIndex& index) : index_(index) {}
  CentrelineIndex::Nearest at(double x, double z) {
    const double dx = x - x_, dz = z - z_;
    if (dx * dx + dz * dz <= kShift * kShift) {
      if (!gathered_) {
        index_.segments_near(x_, z_, d_ + 2.0 * kShift, 16, near_);
        gathered_ = true;
      }
      if (!near_.empty()) return index_.nearest_among(near_, x, z);
    }
    const CentrelineIndex::Nearest n = index_.nearest(x, z);
    x_ = x;
    z_ = z;
    d_ = n.distance;
    gathered_ = false;
    return n;
  }

 private:
  static constexpr double kShift = 1.0;  // metres
  const CentrelineIndex& index_;
  std::vector<std::uint32_t> near_;
  double x_ = 1e300, z_ = 1e300, d_ = 0.0;
  bool gathered_ = false;
};

// Road / sidewalk / ground. The centreline distance is 1-Lipschitz, so a point closer to the
// last queried one than that query's margin to the class borders has its class.
class GroundClasses {
 public:
  explicit GroundClasses(const StaticWorld& w)
      : w_(w),
        borders_{w.config.road_half_width_m,
                 w.config.road_half_width_m + w.config.sidewalk_width_m} {}
  Surface at(double x, double z, NearestCache& nearest) {
    const double dx = x - x_, dz = z - z_;
    if (dx * dx + dz * dz < reach2_) return surface_;
    const double d = nearest.at(x, z).distance;
    const double reach =
        std::min(std::abs(d - borders_[0]), std::abs(d - borders_[1])) * (1.0 - 1e-9) - 1e-9;
    x_ = x;
    z_ = z;
    reach2_ = reach > 0.0 ? reach * reach : -1.0;
    surface_ = ground_surface(w_, d);
    return surface_;
  }

 private:
  const StaticWorld& w_;
  double borders_[2];
  double x_ = 0.0, z_ = 0.0, reach2_ = -1.0;
  Surface surface_ = Surface::Ground;
};

// The caches of one image row: ground heights (ground_y_at) and classes. Every ray's ground
// iteration starts under the camera centre: that height is kept apart, so the cache follows
// the hit points.
class GroundCaches {
 public:
  GroundCaches(const StaticWorld& w, const Eigen::Vector3d& origin)
      : w_(w), nearest_(w.centreline), classes_(w), ox_(origin.x()), oz_(origin.z()) {
    oy_ = height(w.centreline.nearest(ox_, oz_));
  }
  double y_at(double x, double z) {
    if (w_.flat) return w_.flat_ground_y;
    if (x == ox_ && z == oz_) return oy_;
    return height(nearest_.at(x, z));
  }
  Surface surface_at(double x, double z) { return classes_.at(x, z, nearest_); }

 private:
  double height(const CentrelineIndex::Nearest& n) const {
    return (n.found ? n.y : 0.0) + w_.config.camera_height_m;
  }
  const StaticWorld& w_;
  NearestCache nearest_;
  GroundClasses classes_;
  double ox_, oz_, oy_ = 0.0;
};

}  // namespace loopscan::sim
