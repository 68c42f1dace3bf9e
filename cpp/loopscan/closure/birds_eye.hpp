#pragma once
// A bird's-eye search for where a place lies in a query's frame: the structure points of both
// clouds projected on the ground plane (x, z of the camera frame); the place's turned through a
// window of yaws and slid over a window of shifts around each guess, each pose scored by the
// query's smoothed point density under the place's points. Its best distinct poses seed ICP:
// a revisit driven the other way round, or a nearby place whose predicted pose is metres off,
// then starts within about a cell of the truth instead of from blind starts along the street.
#include <vector>

#include <Eigen/Geometry>

#include "loopscan/closure/voxel_cloud.hpp"
#include "loopscan/core/yaw.hpp"

namespace loopscan::closure {

// yaw_rotation / yaw_of (core/yaw.hpp) turn in Candidate::yaw_rad's sense;
// yaw_of(loop.T_query_match) is a loop's heading difference.
using loopscan::yaw_of;
using loopscan::yaw_rotation;
// A camera-frame point within range_m of the camera across the ground (x, z; height ignored).
bool within_ground_range(const Eigen::Vector3f& p, double range_m);

struct BirdsEyeConfig {
  bool enabled = false;          // true: a nearby place's ICP starts from it (not yet the default)
  double cell_m = 1.0;           // grid cell
  double max_range_m = 40.0;     // points farther from their keyframe (x, z) are left out
  double max_shift_m = 10.0;     // searched around each guess, in x and z
  double yaw_window_deg = 24.0;  // searched around each guess's yaw
  double yaw_step_deg = 3.0;
  int peaks = 3;                 // distinct poses returned, best first
  double separation_m = 2.0;     // poses nearer than this and separation_deg are one
  double separation_deg = 10.0;
};

void validate(const BirdsEyeConfig& config);

// The query side: the density of its structure points on the ground plane (square root of the
// count per cell, smoothed over neighbouring cells), built once per query keyframe.
class BirdsEyeGrid {
 public:
  BirdsEyeGrid(const PlaceCloud& query, const BirdsEyeConfig& config = {});
  int size() const { return n_; }  // cells per side
  float at(int row, int col) const { return density_[std::size_t(row) * std::size_t(n_) + std::size_t(col)]; }
  // Cell of a point (x, z); row from z, column from x. May lie outside [0, size()).
  Eigen::Vector2i cell(float x, float z) const;
  const BirdsEyeConfig& config() const { return config_; }

 private:
  BirdsEyeConfig config_;
  int n_ = 0;
  int centre_ = 0;
  std::vector<float> density_;
};

struct BirdsEyePose {
  Eigen::Isometry3d T_query_place = Eigen::Isometry3d::Identity();
  double score = 0;  // summed query density under the place's cells (each cell by sqrt(count))
};

// The best distinct poses T = shift(x, z) * yaw * guess over every guess's window, best first;
// empty when the place has no structure point in range.
std::vector<BirdsEyePose> birds_eye_search(const BirdsEyeGrid& query, const PlaceCloud& place,
                                           const std::vector<Eigen::Isometry3d>& guesses);

}  // namespace loopscan::closure
