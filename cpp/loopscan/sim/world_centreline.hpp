#pragma once
// The street centreline (camera centres of a trajectory) as a set of short segments in a
// uniform 2D grid: nearest-centreline queries for the ground height and road/sidewalk split,
// and footprint clearance checks when objects are placed.
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "loopscan/sim/world_primitives.hpp"

namespace loopscan::sim {

// Drops points closer than min_gap (horizontally) to the previous kept one, then subdivides
// segments longer than max_step, so that segments are short and cheap to bin.
std::vector<Eigen::Vector3d> densify_path(const std::vector<Eigen::Vector3d>& path, double min_gap,
                                          double max_step);

// Points every `step` metres of horizontal arc length, starting at the first point (the last
// partial step is dropped, so a path and the same path driven back give the same samples).
std::vector<Eigen::Vector3d> resample_path(const std::vector<Eigen::Vector3d>& path, double step);

class CentrelineIndex {
 public:
  struct Nearest {
    double distance = std::numeric_limits<double>::infinity();  // horizontal
    double y = 0.0;  // centreline y at the nearest point (interpolated along the segment)
    bool found = false;
  };

  CentrelineIndex() = default;
  CentrelineIndex(const std::vector<Eigen::Vector3d>& path, double cell_m);

  Nearest nearest(double x, double z) const;
  // Smallest horizontal distance from the footprint to the centreline, considering only
  // segments within `search` of it (infinity if none).
  double distance_to(const Footprint& f, double search) const;

  // The segments that come within `radius` of (x, z) (some twice). Empty if more than
  // max_cells grid cells would be searched.
  void segments_near(double x, double z, double radius, std::size_t max_cells,
                     std::vector<std::uint32_t>& out) const;
  // nearest() among the given segments only (exact when they hold every segment within the
  // nearest distance).
  Nearest nearest_among(const std::vector<std::uint32_t>& segments, double x, double z) const;

  std::size_t segment_count() const { return segs_.size(); }
  bool empty() const { return segs_.empty(); }
  double min_y() const { return min_y_; }
  double max_y() const { return max_y_; }

 private:
  struct Segment {
    double ax, az, ay, bx, bz, by;
  };
  void consider(const Segment& s, double x, double z, Nearest& best) const;
  Nearest nearest_linear(double x, double z) const;
  int cell_x(double x) const;
  int cell_z(double z) const;

  std::vector<Segment> segs_;
  double min_x_ = 0.0, min_z_ = 0.0, cell_ = 10.0;
  int nx_ = 0, nz_ = 0;
  std::vector<std::uint32_t> start_;  // CSR: cell c holds items_[start_[c] .. start_[c + 1])
  std::vector<std::uint32_t> items_;
  double min_y_ = 0.0, max_y_ = 0.0;
};

}  // namespace loopscan::sim
