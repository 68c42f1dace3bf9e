#pragma once
// The local point cloud every place keeps for geometric verification: its imitated scan (camera
// frame of its keyframe) reduced to one point per voxel, so that two places can be aligned.
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "loopscan/core/place_cloud.hpp"

namespace loopscan::closure {

using Points3f = std::vector<Eigen::Vector3f>;

struct CloudConfig {
  double voxel_m = 0.5;      // one point (the centroid) per voxel of this size
  int max_points = 6000;     // kept evenly along the voxel order beyond this many
  double max_range_m = 100;  // points farther from the keyframe are dropped
  // A place is classified (ground or structure, a plane fit per point) when a verification
  // first needs it, and most never are; until then it keeps its voxel cloud (up to max_points
  // x 12 bytes). Beyond this many such places the oldest is classified (0: each at once).
  int max_unclassified_places = 2000;
};

// Throws std::invalid_argument naming the first field out of its range.
void validate(const CloudConfig& config);

// One point (the centroid) per occupied voxel, in the order of each voxel's first point
// (deterministic). Non-finite points are skipped.
Points3f voxel_downsample(const Points3f& points, double voxel_m);

// voxel_downsample, the range cut and the count cap of `config`.
Points3f voxel_cloud(const Points3f& scan, const CloudConfig& config = {});

// What a map place keeps (core/place_cloud.hpp): its voxel cloud with the structure points
// (not on the ground) first, so that overlap is measured where places differ (every street
// has a ground).
using loopscan::PlaceCloud;

// Every `stride`-th point (stride >= 1): the cheap subsets of coarse alignment steps.
Points3f every_nth(const Points3f& points, std::size_t stride);

}  // namespace loopscan::closure
