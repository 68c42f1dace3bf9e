#pragma once
// The side of an alignment that is searched: points with a nearest-neighbour index and surface
// normals (for point-to-plane residuals). Built once per query keyframe, then every candidate
// place is aligned onto it.
#include <memory>
#include <vector>

#include "loopscan/closure/place_cloud.hpp"

namespace loopscan::closure {

struct NormalConfig {
  int neighbours = 10;         // points of the local plane fit
  double max_radius_m = 2.0;   // neighbours farther away are not used
  double max_planarity = 0.1;  // smallest / middle eigenvalue above this: no normal (not a plane)
};

class TargetCloud {
 public:
  // Throws std::invalid_argument on an invalid config.
  explicit TargetCloud(Points3f points, const NormalConfig& config = {});
  ~TargetCloud();
  TargetCloud(TargetCloud&&) noexcept;
  TargetCloud& operator=(TargetCloud&&) noexcept;

  // Index of the nearest point within sqrt(max_squared_distance), or -1.
  int nearest(const Eigen::Vector3f& query, float max_squared_distance,
              float* squared_distance) const;

  const Points3f& points() const { return points_; }
  const Points3f& normals() const { return normals_; }  // zero where no plane was found
  bool has_normal(int i) const { return normals_[static_cast<std::size_t>(i)].squaredNorm() > 0.5f; }
  std::size_t size() const { return points_.size(); }
  std::size_t normal_count() const { return normal_count_; }

 private:
  struct Index;
  Points3f points_, normals_;
  std::unique_ptr<Index> index_;
  std::size_t normal_count_ = 0;
};

// The place cloud of a target: points whose normal is within acos(min_vertical) of the up
// axis are ground, the rest (no normal included) structure.
PlaceCloud to_place_cloud(const TargetCloud& cloud, double min_vertical = 0.9);

}  // namespace loopscan::closure
