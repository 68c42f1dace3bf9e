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
    std::uint32_t segment = 0;  // the nearest segment (if found)
  };

  CentrelineIndex() = default;
  CentrelineIndex(const std::vector<Eigen::Vector3d>& path, double cell_m);

  Nearest nearest(double x, double z) const;
  // Smallest horizontal distance from the footprint to the centreline, considering only
  // segments within `search` of it (infinity if none).
  double distance_to(const Footprint& f, double search) const;

  // A segment and its horizontal distance from a point.
  struct Candidate {
    double distance;
    std::uint32_t segment;
  };
  // Every segment that comes within `radius` of (x, z), once, nearest first (ties: lower index).
  // `empty`: a radius known to hold no segment (cells wholly inside it are skipped).
  void segments_within(double x, double z, double empty, double radius,
                       std::vector<Candidate>& out) const;
  // nearest() from candidates sorted by their distance from an anchor `shift` away from (x, z)
  // that hold every segment within (nearest distance at the anchor) + 2 shift of it: a candidate
  // farther than the best so far + shift from the anchor cannot win. Ties go to the lower index.
  Nearest nearest_of(const std::vector<Candidate>& sorted, double shift, double x, double z) const;
  // nearest() by the box tree, bounded first by `hint` (a segment likely near: the last
  // answer nearby). Ties go to the lower index.
  Nearest nearest_from(std::uint32_t hint, double x, double z) const;

  // Arc length along the centreline (from its first point) of the point of `segment` nearest
  // to (x, z): where along the road a ground point lies, for dashed markings.
  double arc_length(std::uint32_t segment, double x, double z) const;

  std::size_t segment_count() const { return segs_.size(); }
  bool empty() const { return segs_.empty(); }
  double min_y() const { return min_y_; }
  double max_y() const { return max_y_; }

 private:
  struct Segment {
    double ax, az, ay, bx, bz, by;
  };
  // Squared distance from (x, z) to the segment and the parameter of the nearest point.
  static double distance2(const Segment& s, double x, double z, double& t) {
    const double ex = s.bx - s.ax, ez = s.bz - s.az, len2 = ex * ex + ez * ez;
    t = len2 > 0.0 ? ((x - s.ax) * ex + (z - s.az) * ez) / len2 : 0.0;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);  // std::clamp
    const double dx = x - (s.ax + t * ex), dz = z - (s.az + t * ez);
    return dx * dx + dz * dz;
  }
  void consider(std::uint32_t segment, double x, double z, Nearest& best) const;
  Nearest nearest_linear(double x, double z) const;
  int cell_x(double x) const;
  int cell_z(double z) const;

  std::vector<Segment> segs_;
  std::vector<double> arc_start_;  // arc length at each segment's first point
  double min_x_ = 0.0, min_z_ = 0.0, cell_ = 10.0;
  int nx_ = 0, nz_ = 0;
  std::vector<std::uint32_t> start_;  // CSR: cell c holds items_[start_[c] .. start_[c + 1])
  std::vector<std::uint32_t> items_;
  double min_y_ = 0.0, max_y_ = 0.0;
  // Bounding boxes over the segments split at the median along the longer side, as an implicit
  // binary tree: node 1 the root, children 2i and 2i + 1, leaf l at leaf_base_ + l holding
  // tree_segs_[kLeaf l, kLeaf (l + 1)). For segments_within and nearest_from.
  struct TreeBox {
    double x0, z0, x1, z1;
  };
  static constexpr std::uint32_t kLeaf = 4;
  std::vector<TreeBox> tree_;
  std::vector<std::uint32_t> tree_segs_;
  std::uint32_t leaf_base_ = 0;
  void build_tree();
  void split_tree(std::uint32_t node, std::uint32_t first_leaf, std::uint32_t leaves);
};

}  // namespace loopscan::sim
