#pragma once
// The side of an alignment that is searched: points with a nearest-neighbour index and surface
// normals (for point-to-plane residuals). Built once per query keyframe, then every candidate
// place is aligned onto it.
#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "loopscan/closure/voxel_cloud.hpp"

namespace loopscan::closure {

struct NormalConfig {
  int neighbours = 12;          // points of the local plane fit
  double max_radius_m = 3.0;    // neighbours farther away are not used
  double max_planarity = 0.25;  // smallest / middle eigenvalue above this: no normal (not a plane)
};

// Normals are fitted on first use (verification touches a fraction of the points), each once,
// by the first thread that needs it: a TargetCloud may be read by several threads at once.
class TargetCloud {
 public:
  // Throws std::invalid_argument on an invalid config or a non-finite point.
  explicit TargetCloud(Points3f points, const NormalConfig& config = {});
  ~TargetCloud();
  TargetCloud(TargetCloud&&) noexcept;
  TargetCloud& operator=(TargetCloud&&) noexcept;

  // Index of the nearest point within sqrt(max_squared_distance), or -1. `hint`, a point
  // likely near (the last answer for a point that moved a little), tightens the search's bound
  // and leaves the answer as it is.
  int nearest(const Eigen::Vector3f& query, float max_squared_distance,
              float* squared_distance, int hint = -1) const;

  // Fits the normals of points 0, stride, 2 stride, ... not fitted yet, on `threads` threads:
  // the normals a lazy fit gives (each point's fit is its own).
  void fit_normals(int threads, std::size_t stride = 1) const;
  bool normal_fitted(int i) const;

  const Points3f& points() const { return points_; }
  bool has_normal(int i) const;                 // a plane was found around point i
  const Eigen::Vector3f& normal(int i) const;   // unit; zero where has_normal is false
  std::size_t size() const { return points_.size(); }

 private:
  struct Index;
  void fit_normal(std::size_t i) const;
  void ensure_fitted(std::size_t i) const;
  Points3f points_;
  NormalConfig config_;
  mutable Points3f normals_;
  // Per point: kUnfitted, kFitting (a thread is fitting it) or kFitted (normals_[i] published).
  std::unique_ptr<std::atomic<std::uint8_t>[]> state_;
  std::unique_ptr<Index> index_;
};

// The place cloud of a target: points whose normal is within acos(min_vertical) of the up
// axis are ground, the rest (no normal included) structure; at most `max_points`, taken evenly
// from each part (ground at most a quarter of them) of an even subset of ~1.5 x max_points.
// `threads` fit the subset's normals (the same cloud whatever the count).
constexpr std::size_t kPlaceCloudPoints = 1500;
constexpr double kGroundMinVertical = 0.9;
PlaceCloud to_place_cloud(const TargetCloud& cloud, std::size_t max_points = kPlaceCloudPoints,
                          double min_vertical = kGroundMinVertical, int threads = 1);

}  // namespace loopscan::closure
