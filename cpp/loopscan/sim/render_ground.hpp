#pragma once
// Per-row caches of the renderer's centreline queries, the cost of every ground pixel: a
// nearest-segment search for the road / sidewalk / ground class and, on streets that are not
// level, for the height of the ground under each step of the ray's iteration. Exact: the same
// answers as CentrelineIndex::nearest (RenderConfig::exact_ground asks it every time).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "loopscan/sim/world_internal.hpp"

namespace loopscan::sim {

// nearest() for a stream of points near each other (one step of the ground iteration along an
// image row). Where the points move slowly, an anchor gathers every segment within D + 2 kShift
// of itself (D: its nearest distance); a point within kShift of the anchor has its nearest
// segment among them, and sorted by distance only the first few need a test. Points that move
// fast (far ground) are searched in the box tree, bounded first by the last answer.
class NearestCache {
 public:
  explicit NearestCache(const CentrelineIndex& index) : index_(index) {}
  CentrelineIndex::Nearest at(double x, double z) {
    const double ax = x - ax_, az = z - az_;
    const double shift = std::sqrt(ax * ax + az * az);
    if (shift <= kShift) return index_.nearest_of(near_, shift, x, z);
    const CentrelineIndex::Nearest n = index_.nearest_from(hint_, x, z);
    if (!n.found) return n;
    const double mx = x - px_, mz = z - pz_;
    if (mx * mx + mz * mz < kSlow * kSlow) {  // the anchor will serve many points
      index_.segments_within(x, z, n.distance * (1.0 - 1e-9) - 1e-6,
                             n.distance + 2.0 * kShift + 1e-6, near_);
      ax_ = x;
      az_ = z;
    }
    hint_ = n.segment;
    px_ = x;
    pz_ = z;
    return n;
  }

 private:
  static constexpr double kShift = 1.0;  // metres
  static constexpr double kSlow = kShift / 8;
  const CentrelineIndex& index_;
  std::vector<CentrelineIndex::Candidate> near_;  // nearest first
  double ax_ = 1e300, az_ = 1e300;                // anchor
  double px_ = 1e300, pz_ = 1e300;                // last point searched in the tree
  std::uint32_t hint_ = 0;
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

// The caches of one image row: ground heights (ground_y_at) for each step of the ground
// iteration (the k-th steps of neighbouring pixels are near each other; the first, under the
// camera centre, is kept apart) and the classes of the hit points.
class GroundCaches {
 public:
  static constexpr int kSteps = 7;  // ground_t_with asks at most 1 + 6 heights a ray
  GroundCaches(const StaticWorld& w, const Eigen::Vector3d& origin, bool exact = false)
      : w_(w),
        classes_nearest_(w.centreline),
        classes_(w),
        ox_(origin.x()),
        oz_(origin.z()),
        exact_(exact) {
    oy_ = height(w.centreline.nearest(ox_, oz_));
    steps_.reserve(kSteps);
    for (int k = 0; k < kSteps; ++k) steps_.emplace_back(w.centreline);
  }
  // Height at the step-th query of a ray's iteration.
  double y_at(int step, double x, double z) {
    if (w_.flat) return w_.flat_ground_y;
    if (x == ox_ && z == oz_) return oy_;
    if (exact_) return height(w_.centreline.nearest(x, z));
    return height(steps_[std::min(step, kSteps - 1)].at(x, z));
  }
  Surface surface_at(double x, double z) {
    if (exact_) return ground_surface(w_, w_.centreline.nearest(x, z).distance);
    return classes_.at(x, z, classes_nearest_);
  }

 private:
  double height(const CentrelineIndex::Nearest& n) const {
    return (n.found ? n.y : 0.0) + w_.config.camera_height_m;
  }
  const StaticWorld& w_;
  std::vector<NearestCache> steps_;
  NearestCache classes_nearest_;
  GroundClasses classes_;
  double ox_, oz_, oy_ = 0.0;
  bool exact_;
};

}  // namespace loopscan::sim
